/* A contact response of your own, built outside the harness as a shared library (docs/plugins.md).

   A scene names it on a contact pair instead of the pair's force rule:

     "contacts": [{"host": "layer", "guest": "probe", "eliminator": "plane",
                   "response": "plugin:build/libhertz.so",
                   "response_parameters": {"stiffness": 2e4, "exponent": 1.5}}]

   (the path relative to the scene file). Each (sub)step, after the pair's detector and eliminator
   ran, the harness calls harness_response_forces with the step's pushes (the eliminator's
   directions, depths, the nodes each contact leans on and their weights) and both bodies' state;
   the plug-in writes the forces it applies per node. The harness adds them to the step's other
   forces, books their work in the energy audit and records the plug-in's name in summary.json
   (pairs[].response, "plugin:NAME").

   The interface is C (any language that exports C symbols can implement it) and versioned: a
   plug-in returns the HARNESS_RESPONSE_ABI it was compiled against from harness_response_abi, and
   a harness with another version refuses it (exit 2) rather than misreading its structures. This
   header changes only with the version. Every array is row-major, in the scene's node numbering
   (the order a body's nodes have in the scene: the shape's generator or mesh file), SI units.

   Limits of version 1: the response reports no stiffness, so the stability guard does not see
   it (a stiff law needs a smaller time.dt) and the implicit integrator refuses it; it runs
   on the CPU only (--device refuses it); calls for one pair come from one thread at a time. */
#ifndef HARNESS_RESPONSE_H
#define HARNESS_RESPONSE_H

#define HARNESS_RESPONSE_ABI 1

#ifdef __cplusplus
extern "C" {
#endif

/* One contact's push, as the pair's eliminator made it. */
typedef struct harness_push {
  int way;             /* 0: a guest node inside the host; 1: a host node inside the guest (two_sided) */
  int node;            /* the pushed node: in the guest (way 0) or the host (way 1), scene numbering */
  int hosts[3];        /* the nodes of the other body it leans on, -1 where unused (none: no host) */
  double weights[3];   /* their shares of the reaction (sum 1 over the used ones) */
  double direction[3]; /* the unit push on `node` */
  double depth;        /* m, the eliminator's depth (<= 0: not inside by its measure) */
} harness_push;

/* One body's state. */
typedef struct harness_body {
  const char* name;      /* the scene's body name */
  int n;                 /* its nodes */
  const double* x;       /* n x 3 positions, m */
  const double* v;       /* n x 3 velocities, m/s */
  const double* m;       /* n masses, kg */
  const double* normals; /* n x 3 unit outward normals at the surface nodes the pushes name (each
                            push's node and the nodes it leans on), zero rows elsewhere */
} harness_body;

/* The pair's contacts this (sub)step. */
typedef struct harness_contacts {
  const char* pair;          /* the pair's label (contacts.N.label) */
  double h;                  /* the (sub)step, s */
  int count;                 /* pushes */
  const harness_push* push;  /* count of them */
} harness_contacts;

/* The symbols a plug-in exports (all five are required):

   int harness_response_abi(void);
     HARNESS_RESPONSE_ABI as the plug-in saw it when compiled.

   const char* harness_response_name(void);
     Its name in the outputs (a static string).

   void* harness_response_create(int count, const char* const* names, const double* values,
                                 char* error, int error_size);
     Once per pair, before the first step: the scene's response_parameters (count of them, in
     the order of their names). Returns the pair's state (any non-null pointer), or null with a
     one-line message in error (at most error_size bytes, terminated): the run then stops with
     exit 2 naming contacts.N.response_parameters. Refuse names you do not know.

   int harness_response_forces(void* state, const harness_contacts* contacts,
                               const harness_body* guest, const harness_body* host,
                               double* f_guest, double* f_host, char* error, int error_size);
     Each (sub)step with at least one push (a step without contacts does not call it): add the forces (N) on the guest's and the host's nodes into f_guest and
     f_host (guest->n x 3 and host->n x 3, zero on entry). Return 0, or non-zero with a
     message in error: the run then fails at that step (exit 3, summary.json status "error"
     with the message; the last good state is kept). Non-finite forces fail the step too.

   void harness_response_destroy(void* state);
     When the run ends. */
#define HARNESS_RESPONSE_EXPORT __attribute__((visibility("default")))

typedef int (*harness_response_abi_fn)(void);
typedef const char* (*harness_response_name_fn)(void);
typedef void* (*harness_response_create_fn)(int count, const char* const* names, const double* values,
                                            char* error, int error_size);
typedef int (*harness_response_forces_fn)(void* state, const harness_contacts* contacts,
                                          const harness_body* guest, const harness_body* host,
                                          double* f_guest, double* f_host, char* error, int error_size);
typedef void (*harness_response_destroy_fn)(void* state);

#ifdef __cplusplus
}
#endif

#endif /* HARNESS_RESPONSE_H */
