/* A Hertz-like penalty with contact damping, as a plug-in (docs/plugins.md):
     F = max(0, stiffness * depth^exponent - damping * v_n)
   per contact along the eliminator's push on its node, the reaction on the nodes it leans on by
   their weights; v_n is the node's speed away from them along the push. Parameters: stiffness
   (N/m^exponent, required), exponent (default 1), damping (N s/m, default 0). With exponent 1 and
   no damping it is the built-in linear penalty ("force": {"stiffness": k}). */
#include <harness/response.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  double stiffness, exponent, damping;
} hertz;

HARNESS_RESPONSE_EXPORT int harness_response_abi(void) { return HARNESS_RESPONSE_ABI; }

HARNESS_RESPONSE_EXPORT const char* harness_response_name(void) { return "hertz"; }

HARNESS_RESPONSE_EXPORT void* harness_response_create(int count, const char* const* names, const double* values,
                                                      char* error, int error_size) {
  hertz h = {-1.0, 1.0, 0.0};
  for (int i = 0; i < count; ++i) {
    if (strcmp(names[i], "stiffness") == 0) h.stiffness = values[i];
    else if (strcmp(names[i], "exponent") == 0) h.exponent = values[i];
    else if (strcmp(names[i], "damping") == 0) h.damping = values[i];
    else {
      snprintf(error, (size_t)error_size, "unknown parameter \"%s\" (stiffness, exponent, damping)", names[i]);
      return NULL;
    }
  }
  if (!(h.stiffness >= 0.0)) {
    snprintf(error, (size_t)error_size, "stiffness: required, >= 0");
    return NULL;
  }
  if (!(h.exponent >= 1.0 && h.exponent <= 3.0) || !(h.damping >= 0.0)) {
    snprintf(error, (size_t)error_size, "exponent 1 to 3, damping >= 0");
    return NULL;
  }
  hertz* p = malloc(sizeof *p);
  if (p) *p = h;
  else snprintf(error, (size_t)error_size, "out of memory");
  return p;
}

HARNESS_RESPONSE_EXPORT int harness_response_forces(void* state, const harness_contacts* c, const harness_body* guest,
                                                    const harness_body* host, double* f_guest, double* f_host,
                                                    char* error, int error_size) {
  const hertz* h = state;
  (void)error, (void)error_size;
  for (int i = 0; i < c->count; ++i) {
    const harness_push* p = &c->push[i];
    if (p->hosts[0] < 0 || p->depth <= 0.0) continue; /* nothing to push against, or not inside */
    const harness_body* own = p->way == 0 ? guest : host;
    const harness_body* other = p->way == 0 ? host : guest;
    double* f_own = p->way == 0 ? f_guest : f_host;
    double* f_other = p->way == 0 ? f_host : f_guest;
    double F = h->stiffness * (h->exponent == 1.0 ? p->depth : pow(p->depth, h->exponent));
    if (h->damping > 0.0) {
      double vn = 0.0;
      for (int k = 0; k < 3; ++k) {
        double rel = own->v[3 * p->node + k];
        for (int j = 0; j < 3; ++j)
          if (p->hosts[j] >= 0) rel -= p->weights[j] * other->v[3 * p->hosts[j] + k];
        vn += rel * p->direction[k];
      }
      F -= h->damping * vn;
      if (F < 0.0) F = 0.0;
    }
    for (int k = 0; k < 3; ++k) {
      const double fk = F * p->direction[k];
      f_own[3 * p->node + k] += fk;
      for (int j = 0; j < 3; ++j)
        if (p->hosts[j] >= 0) f_other[3 * p->hosts[j] + k] -= p->weights[j] * fk;
    }
  }
  return 0;
}

HARNESS_RESPONSE_EXPORT void harness_response_destroy(void* state) { free(state); }
