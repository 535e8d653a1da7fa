/* The sweep plot of a dtmap built without PLplot (CMake's DTM_PLOT found
 * no PLplot, so this file replaces plot.c): the sweep still writes its CSV,
 * and asking for a plot says what to install. */
#include "cli-impl.h"
#include "dtmap/error.h"

int dtm_cli_can_plot(void) { return 0; }

int dtm_cli_sweep_plot_titled(const char *path, const char *title, const dtm_sweep_row *rows, int n) {
  (void)title, (void)rows, (void)n;
  return DTM_ERR(DTM_ERR_INPUT,
                 "%s: this dtmap was built without PLplot, so it cannot draw the sweep plot; leave out --plot "
                 "for the CSV alone, or install libplplot-dev and plplot-driver-cairo and rebuild",
                 path);
}

int dtm_cli_sweep_plot(const char *path, const dtm_sweep_row *rows, int n) {
  return dtm_cli_sweep_plot_titled(path, NULL, rows, n);
}
