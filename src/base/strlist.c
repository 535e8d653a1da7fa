/* Lists of names for messages ("groups of that dimension: 'a', 'b'"), built
 * in a caller's fixed buffer. */
#include <stdio.h>
#include <string.h>

#include "base.h"

void dtm_strlist_add(char *buf, size_t len, const char *item, int quote) {
  size_t used = strlen(buf);
  if (used + 1 >= len) return;
  snprintf(buf + used, len - used, quote ? "%s'%s'" : "%s%s", used ? ", " : "", item);
}
