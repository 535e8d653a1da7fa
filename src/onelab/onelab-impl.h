/* Private to the ONELAB client (src/onelab/): the wire protocol Gmsh speaks
 * with its solvers (a header of two native ints, message type and body
 * length, then the body), ONELAB parameters in their text form (fields
 * separated by NUL bytes, as ONELAB 1.3 writes them), the named material
 * library, dtmap's parameter panel and the scene it turns into. Only
 * libdtmap's public API is used: the client is linked into the dtmap
 * executable, not into the library. */
#ifndef DTM_ONELAB_IMPL_H
#define DTM_ONELAB_IMPL_H

#include <stddef.h>

#include "dtmap/material.h"
#include "dtmap/mesh.h"
#include "dtmap/scene.h"

/* Message types of Gmsh's socket protocol (the subset dtmap sends or reads). */
enum {
  OL_START = 1,        /* client -> Gmsh: "PID" */
  OL_STOP = 2,         /* client -> Gmsh: goodbye */
  OL_INFO = 10,        /* a line for Gmsh's message console */
  OL_WARNING = 11,     /* a warning */
  OL_ERROR = 12,       /* an error (Gmsh counts it and shows it) */
  OL_PROGRESS = 13,    /* a line for Gmsh's status bar */
  OL_MERGE_FILE = 20,  /* ask Gmsh to merge a file (a .msh with views) */
  OL_PARAMETER = 23,   /* set a parameter / the reply to a query */
  OL_QUERY = 24,       /* ask for one parameter (or a Gmsh option "A.B") */
  OL_NOT_FOUND = 29,   /* reply: no such parameter */
  OL_PARAMETER_MAX = 4 /* (not a type) */
};

/* A connection to Gmsh's ONELAB server. */
typedef struct {
  int fd;         /* connected socket, -1 when closed */
  char name[128]; /* the client's name as Gmsh gave it ("dtmap") */
  double timeout; /* seconds to wait for a reply */
} ol_conn;

/* Connect to address (a Unix socket path, or host:port) as client name and
 * send START. DTM_ERR_INPUT naming the address when it cannot connect. */
int dtm_ol_connect(ol_conn *c, const char *name, const char *address);
/* Send STOP and close. Safe on a closed connection. */
void dtm_ol_close(ol_conn *c);
/* Send one message: type, then len bytes of body. */
int dtm_ol_send(ol_conn *c, int type, const char *body, size_t len);
/* Send a NUL-terminated text message (INFO, PROGRESS, MERGE_FILE, ...). */
int dtm_ol_send_text(ol_conn *c, int type, const char *text);
/* Receive one message within c->timeout; *body is malloc'd (NUL-terminated,
 * len bytes before the NUL), the caller frees it. */
int dtm_ol_recv(ol_conn *c, int *type, char **body, size_t *len);

#define OL_MAX_CHOICES 48
#define OL_MAX_ATTRS 6

/* A ONELAB parameter, number or string, with the fields dtmap uses. */
typedef struct {
  int is_string;                         /* 1: string parameter; 0: number */
  char name[256];                        /* "dtmap/1Time/safety" */
  char label[128];                       /* shown instead of the name's last part, or "" */
  char help[256];                        /* tooltip, or "" */
  int visible, read_only;                /* flags */
  int never_changed;                     /* 1: changing it does not mark the client as changed */
  int nattrs;                            /* attributes in use */
  char attr_key[OL_MAX_ATTRS][24];       /* "Highlight", "Units", ... */
  char attr_val[OL_MAX_ATTRS][64];       /* their values */
  double value;                          /* number: the value */
  double min, max, step;                 /* number: slider range (+-1e200 when unbounded) */
  int nchoices;                          /* choices of a number (with labels) or a string */
  double choice[OL_MAX_CHOICES];         /* number choices */
  char choice_label[OL_MAX_CHOICES][64]; /* label of each number choice, or the string choices */
  char svalue[4096];                     /* string: the value */
  char kind[16];                         /* string: "generic" or "file" */
} ol_param;

/* A number (string) parameter with defaults: visible, unbounded, no choices. */
void dtm_ol_number(ol_param *p, const char *name, double value, const char *label);
void dtm_ol_string(ol_param *p, const char *name, const char *value, const char *label);
/* Add an attribute (ignored beyond OL_MAX_ATTRS). */
void dtm_ol_attr(ol_param *p, const char *key, const char *value);
/* Add a choice (a number with its label, or a string). */
void dtm_ol_choice(ol_param *p, double value, const char *label);
/* The text form of p into a malloc'd buffer of *len bytes. */
int dtm_ol_encode(const ol_param *p, char **out, size_t *len);
/* Read the text form (len bytes) into p. DTM_ERR_INPUT when malformed. */
int dtm_ol_decode(const char *msg, size_t len, ol_param *p);

/* Set p on the server. */
int dtm_ol_set(ol_conn *c, const ol_param *p);
/* Ask the server for the parameter name of p's type; *found = 0 when it has
 * none, else p holds the server's copy. Names with a dot and no slash
 * ("General.FileName") are Gmsh options. */
int dtm_ol_get(ol_conn *c, const char *name, int is_string, ol_param *p, int *found);
/* Define p: when the server already has it, keep the server's value (the
 * user's) and send p's other fields with that value; else send p. On
 * return p->value / p->svalue is the value in force. */
int dtm_ol_define(ol_conn *c, ol_param *p);
/* Wait until the server has handled every message sent so far (a query
 * round trip). */
int dtm_ol_sync(ol_conn *c);
/* The action Gmsh asks of this client (NAME/Action: "initialize", "check",
 * "compute", or "stop" once the user pressed Stop), "" when none. */
int dtm_ol_action(ol_conn *c, char *action, size_t n);

/* The material properties the panel offers (attribute names of
 * <material>), the name of property p's unit in a system of units (the
 * scene's units string: NULL or "SI", "mm-t-s"; "" for nu) and the SI value
 * of one such unit (1 in SI). */
#define OL_NPROPS 10
extern const char *const dtm_ol_prop_names[OL_NPROPS];
const char *dtm_ol_prop_unit(const char *system, int p);
double dtm_ol_prop_si(const char *system, int p);

/* One material of the built-in library. */
typedef struct {
  const char *name;       /* "granite" */
  double prop[OL_NPROPS]; /* SI values; NaN where the library has none */
  const char *source;     /* where the values come from (docs/materials.md) */
} ol_material;

/* The library, terminated by a NULL name. */
extern const ol_material dtm_ol_materials[];
/* Number of entries in the library. */
int dtm_ol_material_count(void);

/* Built-in effects the panel can switch on, in the order they run when the
 * scene does not say. */
#define OL_NEFFECTS 5
extern const char *const dtm_ol_effect_names[OL_NEFFECTS];

/* The material choice of one physical group, and the section of a group
 * below the analysed dimension (a curve or surface in or on the model). */
typedef struct {
  char ref[128];                /* the group as a scene names it (name, or number) */
  int dim;                      /* the group's dimension (the analysed one, or below for a section) */
  int kind;                     /* below the analysed dimension: DTM_SECTION_TRUSS or DTM_SECTION_BEAM
                                   (curves), DTM_SECTION_MEMBRANE or DTM_SECTION_SHELL (surfaces) when
                                   chosen, -1: none (not analysed); -1 at the analysed dimension (the
                                   effects' formulation) */
  double measure;               /* the section's area (truss), thickness (membrane, shell) or radius (a
                                   beam of circular profile), in the scene's units (m^2 | mm^2, m | mm) */
  const dtm_section *scene_sec; /* the base scene's section of the group, or NULL: a shell or beam
                                   chosen in the panel keeps its convention, shear factor and (beam)
                                   profile and orientation */
  int choice;                   /* 0: custom; 1..n: library entry choice-1; n+1: the scene's own */
  char scene_name[128];         /* the scene's material for this group, or "" */
  double prop[OL_NPROPS];       /* the values in force, in the scene's units (NaN: not given) */
} ol_group;

/* What the panel holds, read back from the server. */
typedef struct {
  int effect_on[OL_NEFFECTS]; /* built-in effect switched on */
  int formulation;            /* elastic: 0 3d, 1 plane strain, 2 plane stress, 3 bar */
  double xi;                  /* damping ratio */
  double safety;              /* 0 < safety <= 1 */
  double target;              /* s; 0: none */
  double duration;            /* s; 0: none */
  int posterior;              /* also the global estimate */
  const char *units;          /* the base scene's system of units (dtm_scene_units), else the panel's
                                 choice ("SI" or "mm-t-s"):
                                 every length and material value below is in it, the times in s */
  double mesh_size;           /* the scene's length unit; 0: the geometry's own sizes */
  int save_scene;             /* write the panel as a scene after the run */
  char scene_out[4096];       /* where */
  int ngroups;                /* groups of the analysed dimension (+1 for "no group"), then those below */
  int nanalysed;              /* the first nanalysed groups are of the analysed dimension */
  ol_group *groups;           /* [ngroups] */
} ol_panel;

/* Whether group i of the panel goes into the scene: a group of the analysed
 * dimension, or one below it with a section. */
int dtm_ol_group_in_scene(const ol_panel *panel, int i);

/* Everything the client knows about the model it works on. */
typedef struct {
  char model[4096];   /* the file open in Gmsh (General.FileName) */
  char scene[4096];   /* MODEL.xml beside it (or given), or "" */
  dtm_scene *base;    /* that scene, or NULL */
  const char *source; /* the geometry or mesh to analyse (model or the scene's) */
  int source_is_mesh; /* source is a .msh */
  int dim;            /* dimension analysed */
  int ngroups;        /* physical groups of that dimension */
  dtm_group *groups;  /* [ngroups] (owned) */
  int nlower;         /* physical groups below it that a section can take: surfaces, then curves
                         (none whose name or number an analysed group already answers to) */
  dtm_group *lower;   /* [nlower] (owned) */
} ol_model;

/* Declare the panel under "NAME/" from the model and its base scene, read
 * back the values in force into panel (which the caller frees with
 * dtm_ol_panel_free). */
int dtm_ol_panel_declare(ol_conn *c, const ol_model *m, ol_panel *panel);
void dtm_ol_panel_free(ol_panel *panel);
/* The scene the panel describes, as XML text (malloc'd, NUL-terminated). */
int dtm_ol_scene_text(const ol_model *m, const ol_panel *panel, char **xml);
/* Find the model open in Gmsh, its scene (scene_arg, or MODEL.xml beside
 * it) and, opened in dtmap's Gmsh (started by the caller), its dimension,
 * its physical groups of that dimension and those below it. Free with
 * dtm_ol_model_free. */
int dtm_ol_model_load(ol_conn *c, const char *scene_arg, ol_model *m);
void dtm_ol_model_free(ol_model *m);
/* Group g as a scene names it: its name, or its number when unnamed. */
void dtm_ol_group_ref(const dtm_group *g, char *ref, size_t n);
/* Analyse the panel's scene, write the result, publish its figures under
 * NAME/9Results and hand it to Gmsh to merge; posterior forces the global
 * estimate. */
int dtm_ol_compute(ol_conn *c, const ol_model *m, const ol_panel *panel, int posterior);
/* Copy the data sections of the result msh (and msh.opt) to out (+ .opt). */
int dtm_ol_views_only(const char *msh, const char *out);

#endif
