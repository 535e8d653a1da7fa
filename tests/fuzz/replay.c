/* Replays a fuzz corpus through a libFuzzer target without libFuzzer, as
 * SQLite's fuzzcheck does: every regular file in each directory given on
 * the command line is passed once to LLVMFuzzerTestOneInput. A finding
 * aborts (the target's own checks) or trips the sanitizers of the ASan
 * build; otherwise the program prints how many inputs it ran and exits 0.
 * Exit 1 when a directory cannot be read or holds no input (a corpus that
 * silently vanished would make the test pass without testing). */
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static unsigned char *read_file(const char *path, size_t *n) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  size_t cap = 1 << 16, len = 0, got;
  unsigned char *b = malloc(cap);
  while (b && (got = fread(b + len, 1, cap - len, f)) > 0)
    if ((len += got) == cap) {
      unsigned char *bigger = realloc(b, cap *= 2);
      if (!bigger) free(b);
      b = bigger;
    }
  fclose(f);
  *n = len;
  return b;
}

static int replay_dir(const char *dir) {
  DIR *d = opendir(dir);
  int count = 0;
  if (!d) return fprintf(stderr, "replay: cannot open %s\n", dir), -1;
  for (struct dirent *e; (e = readdir(d));) {
    char path[4096];
    size_t n = 0;
    if (e->d_name[0] == '.' || !strcmp(e->d_name, "README.md")) continue;
    snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
    unsigned char *b = read_file(path, &n);
    if (!b) return closedir(d), fprintf(stderr, "replay: cannot read %s\n", path), -1;
    LLVMFuzzerTestOneInput(b, n);
    free(b);
    count++;
  }
  closedir(d);
  return count;
}

int main(int argc, char **argv) {
  int total = 0;
  for (int i = 1; i < argc; i++) {
    int n = replay_dir(argv[i]);
    if (n <= 0) return fprintf(stderr, "replay: no input in %s\n", argv[i]), 1;
    printf("replayed %d inputs from %s\n", n, argv[i]);
    total += n;
  }
  return total > 0 ? 0 : 1;
}
