#include "core/collision/responses/plugin.hpp"

#include "core/plugin/harness/response.h"
#include "core/world.hpp"

#include <dlfcn.h>

#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace harness {

namespace {

// The library and the pair's state: dlclose after the state is destroyed.
struct Loaded {
  void* lib = nullptr;
  void* state = nullptr;
  harness_response_forces_fn forces = nullptr;
  harness_response_destroy_fn destroy = nullptr;
  std::string name, pair;
  // Scratch reused each call, in the scene's numbering: pushes, each body's x, v, m, normals,
  // and the forces the plug-in writes.
  std::vector<harness_push> push;
  std::vector<int> named[2];  // per body (guest, host): the nodes the pushes name, scene numbering
  struct Side {
    std::vector<double> x, v, m, normals, f;
  } side[2];
  ~Loaded() {
    if (state && destroy) destroy(state);
    if (lib) dlclose(lib);
  }
};

// A body's state for the plug-in: x, v and m straight from the world where its nodes keep the
// scene's numbering (no copy), else copied into it; normals only at the surface nodes `named` (the
// pushes' nodes, scene numbering), zero rows elsewhere; forces zeroed.
void fill_body(const World& w, int bi, const std::vector<int>& named, Loaded::Side& s, harness_body& out) {
  const Body& b = w.bodies[bi];
  const auto n = static_cast<std::size_t>(b.size());
  out.name = b.name.c_str();
  out.n = b.size();
  if (b.scene_node.empty()) {
    out.x = w.x[b.begin].data(), out.v = w.v[b.begin].data(), out.m = &w.m[b.begin];
  } else {
    s.x.resize(3 * n), s.v.resize(3 * n), s.m.resize(n);
    for (int i = 0; i < b.size(); ++i) {
      const auto q = static_cast<std::size_t>(b.scene_index(i));
      const int g = b.begin + i;
      for (int k = 0; k < 3; ++k) s.x[3 * q + k] = w.x[g][k], s.v[3 * q + k] = w.v[g][k];
      s.m[q] = w.m[g];
    }
    out.x = s.x.data(), out.v = s.v.data(), out.m = s.m.data();
  }
  s.normals.assign(3 * n, 0.0);
  s.f.assign(3 * n, 0.0);
  for (const int q : named) {
    const int i = b.local_of_scene(q);
    if (i >= b.n_surface || b.vf_start.empty() || s.normals[3 * q] != 0.0 || s.normals[3 * q + 1] != 0.0 || s.normals[3 * q + 2] != 0.0) continue;
    const Vec3 nv = vertex_normal(w, bi, i);
    const double len = nv.norm();
    if (len > 0.0)
      for (int k = 0; k < 3; ++k) s.normals[3 * q + k] = nv[k] / len;
  }
  out.normals = s.normals.data();
}

void add_forces(const World& w, int bi, const Loaded::Side& s, Points& f, const Loaded& l) {
  const Body& b = w.bodies[bi];
  for (int q = 0; q < b.size(); ++q) {
    const Vec3 fq(s.f[3 * q], s.f[3 * q + 1], s.f[3 * q + 2]);
    if (!fq.allFinite())
      throw std::runtime_error("response plugin:" + l.name + " (pair " + l.pair + "): the force on node " +
                               std::to_string(q) + " of body " + b.name + " is not finite");
    f[b.begin + b.local_of_scene(q)] += fq;
  }
}

template <class F>
F symbol(void* lib, const char* name, const std::string& where, const std::string& file) {
  dlerror();
  void* p = dlsym(lib, name);
  if (!p) {
    dlclose(lib);
    throw InputError(where, file + " has no symbol " + name + " (core/plugin/harness/response.h lists the five a plug-in exports)");
  }
  return reinterpret_cast<F>(p);
}

}  // namespace

OwnResponse load_response_plugin(const Scene& scene, const ContactPairSpec& pair) {
  const std::string where = scene.file + ": " + pair.path + ".response";
  const std::string& file = pair.plugin;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) throw InputError(where, "no plug-in file " + file);
  void* lib = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!lib) {
    const char* e = dlerror();
    throw InputError(where, "cannot load " + file + ": " + (e ? e : "not a shared library"));
  }
  const auto abi = symbol<harness_response_abi_fn>(lib, "harness_response_abi", where, file);
  const auto name = symbol<harness_response_name_fn>(lib, "harness_response_name", where, file);
  const auto create = symbol<harness_response_create_fn>(lib, "harness_response_create", where, file);
  auto l = std::make_shared<Loaded>();
  l->forces = symbol<harness_response_forces_fn>(lib, "harness_response_forces", where, file);
  l->destroy = symbol<harness_response_destroy_fn>(lib, "harness_response_destroy", where, file);
  if (const int v = abi(); v != HARNESS_RESPONSE_ABI) {
    dlclose(lib);
    throw InputError(where, file + " was built for response interface version " + std::to_string(v) +
                                ", this harness has version " + std::to_string(HARNESS_RESPONSE_ABI) +
                                ": rebuild it against this harness's core/plugin/harness/response.h");
  }
  l->lib = lib;
  const char* nm = name();
  l->name = nm && *nm ? nm : std::filesystem::path(file).stem().string();
  l->pair = pair.label;
  std::vector<const char*> names;
  std::vector<double> values;
  for (const auto& [k, v] : pair.plugin_parameters) names.push_back(k.c_str()), values.push_back(v);
  char error[512] = "";
  l->state = create(static_cast<int>(names.size()), names.data(), values.data(), error, sizeof error);
  error[sizeof error - 1] = '\0';
  if (!l->state)
    throw InputError(scene.file + ": " + pair.path + ".response_parameters",
                     "plugin:" + l->name + " refused them: " + (*error ? error : "(no message)"));

  OwnResponse r;
  r.name = "plugin:" + l->name;
  const int guest = pair.spec.guest, host = pair.spec.host;
  r.force = [l, guest, host](const World& w, const std::vector<Push>& pushes, double h, Points& f) {
    const Body& g = w.bodies[guest];
    const Body& hb = w.bodies[host];
    l->push.resize(pushes.size());
    l->named[0].clear(), l->named[1].clear();
    for (std::size_t i = 0; i < pushes.size(); ++i) {
      const Push& p = pushes[i];
      const bool forward = p.guest >= g.begin && p.guest < g.end;
      const Body& own = forward ? g : hb;
      const Body& other = forward ? hb : g;
      harness_push& c = l->push[i];
      c.way = forward ? 0 : 1;
      c.node = own.scene_index(p.guest - own.begin);
      for (int j = 0; j < 3; ++j) {
        c.hosts[j] = j < p.count ? other.scene_index(p.hosts[j] - other.begin) : -1;
        c.weights[j] = j < p.count ? p.weight[j] : 0.0;
        c.direction[j] = p.n[j];
      }
      c.depth = p.depth;
      l->named[c.way].push_back(c.node);
      for (int j = 0; j < p.count; ++j) l->named[1 - c.way].push_back(c.hosts[j]);
    }
    if (pushes.empty()) return;  // nothing to respond to: the plug-in is not called
    harness_contacts cs{l->pair.c_str(), h, static_cast<int>(pushes.size()), l->push.data()};
    harness_body gb{}, hbv{};
    fill_body(w, guest, l->named[0], l->side[0], gb);
    fill_body(w, host, l->named[1], l->side[1], hbv);
    char msg[512] = "";
    const int rc = l->forces(l->state, &cs, &gb, &hbv, l->side[0].f.data(), l->side[1].f.data(), msg, sizeof msg);
    msg[sizeof msg - 1] = '\0';
    if (rc != 0)
      throw std::runtime_error("response plugin:" + l->name + " (pair " + l->pair + ") returned " + std::to_string(rc) +
                               ": " + (*msg ? msg : "(no message)"));
    add_forces(w, guest, l->side[0], f, *l);
    add_forces(w, host, l->side[1], f, *l);
  };
  return r;
}

}  // namespace harness
