/* Commands of the dtmap CLI that live outside main.c, which dispatches to
 * them. Each takes main's argc and argv unchanged (argv[1] is the command
 * name) and returns the process exit code: 0 success, 1 target or
 * verification not met, 2 bad input or usage, 3 internal error. */
#ifndef DTM_CLI_H
#define DTM_CLI_H

/* `dtmap sweep SCENE.xml --sizes h1,h2,... [--csv F] [--plot F.png] [-v|-q]` */
int dtm_cli_sweep(int argc, char **argv);

#endif
