/* Helpers for the tests that drive Gmsh's own ONELAB machinery (t804,
 * t805, t973): a fresh Gmsh session with an empty ONELAB database and a model
 * open, on a solver socket of the test program's own (Gmsh's default,
 * ~/.gmshsock<id>, is the one t802 listens on when ctest runs them side by
 * side); dtmap run as Gmsh's ONELAB solver for one action; numbers set and
 * read in the database, and a parameter's Units checked. Failures end the cmocka test. */
#ifndef DTM_TEST_ONELAB_H
#define DTM_TEST_ONELAB_H

/* Gmsh begun, the database cleared, model opened; test names the socket. */
void tu_onelab_session(const char *model, const char *test);
/* dtmap run by gmshOnelabRun for action ("check": declare the panel; "compute"). */
void tu_onelab_run(const char *action);
void tu_onelab_set_number(const char *name, double v);
/* The number name holds, NaN when it holds none or several. */
double tu_onelab_get_number(const char *name);
/* The Units attribute of the ONELAB parameter name is unit ("" for none). */
void tu_onelab_assert_units(const char *name, const char *unit);
/* The panel asked to save its scene to saved, then "compute": the
 * recommended and smallest steps it shows into *rec and *dmin, Gmsh ended,
 * and the saved scene's text returned (owned: free). */
char *tu_onelab_compute_saved(const char *saved, double *rec, double *dmin);

#endif
