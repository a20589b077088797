// Python callables as contact responses (harness.Simulation(response=...), harness.run(response=...)):
// each (sub)step, after detection and the eliminator's pushes, the callable gets the pair's contacts
// and both bodies' state and returns the forces per node (docs/python.md, "A response of your own").
#include "python/module.hpp"

#include "core/world.hpp"

#include <pybind11/numpy.h>

#include <memory>
#include <stdexcept>

namespace harness::py {

namespace {

// The callable, held so that copies of the std::function (made without the GIL: run_scene copies
// its options) never touch Python's reference counts; released with the GIL taken.
struct Held {
  explicit Held(pyb::object f) : fn(std::move(f)) {}
  ~Held() {
    pyb::gil_scoped_acquire acquire;
    fn = pyb::object();
  }
  pyb::object fn;
};

pyb::array_t<double> rows3(std::size_t n) {
  pyb::array_t<double> a({static_cast<pyb::ssize_t>(n), pyb::ssize_t{3}});
  std::fill(a.mutable_data(), a.mutable_data() + 3 * n, 0.0);
  return a;
}

// A body's state in the scene's numbering: name, x, v (m, m/s, (n, 3)), m (kg, (n,)), normals (unit
// outward normals of the surface nodes, zero rows for the others, (n, 3)).
pyb::dict body_state(const World& w, int bi) {
  const Body& b = w.bodies[bi];
  const auto n = static_cast<std::size_t>(b.size());
  pyb::array_t<double> x = rows3(n), v = rows3(n), nrm = rows3(n);
  pyb::array_t<double> m(static_cast<pyb::ssize_t>(n));
  auto X = x.mutable_unchecked<2>(), V = v.mutable_unchecked<2>(), N = nrm.mutable_unchecked<2>();
  auto M = m.mutable_unchecked<1>();
  for (int i = 0; i < b.size(); ++i) {
    const int q = b.scene_index(i), g = b.begin + i;
    for (int k = 0; k < 3; ++k) X(q, k) = w.x[g][k], V(q, k) = w.v[g][k];
    M(q) = w.m[g];
    if (i < b.n_surface && !b.vf_start.empty()) {
      const Vec3 nv = vertex_normal(w, bi, i);
      const double len = nv.norm();
      if (len > 0.0)
        for (int k = 0; k < 3; ++k) N(q, k) = nv[k] / len;
    }
  }
  pyb::dict d;
  d["name"] = b.name, d["x"] = x, d["v"] = v, d["m"] = m, d["normals"] = nrm;
  return d;
}

// The pushes as columns: way (0: a guest node inside the host; 1: a host node inside the guest,
// two-sided), node (body-local, scene numbering, in the guest's body for way 0), hosts and weights
// ((k, 3): the nodes of the other body it pushes against, -1 where unused, and their shares),
// direction (the unit push on `node`), depth (m, the eliminator's).
pyb::dict contact_columns(const World& w, const ContactSpec& spec, const std::vector<Push>& pushes, double h,
                          const std::string& label) {
  const std::size_t k = pushes.size();
  pyb::array_t<long long> way(static_cast<pyb::ssize_t>(k)), node(static_cast<pyb::ssize_t>(k));
  pyb::array_t<long long> hosts({static_cast<pyb::ssize_t>(k), pyb::ssize_t{3}});
  pyb::array_t<double> weights = rows3(k), dir = rows3(k), depth(static_cast<pyb::ssize_t>(k));
  auto W = way.mutable_unchecked<1>(), Nd = node.mutable_unchecked<1>();
  auto H = hosts.mutable_unchecked<2>();
  auto Wt = weights.mutable_unchecked<2>(), D = dir.mutable_unchecked<2>();
  auto Dp = depth.mutable_unchecked<1>();
  const Body& g = w.bodies[spec.guest];
  const Body& hb = w.bodies[spec.host];
  for (std::size_t i = 0; i < k; ++i) {
    const Push& p = pushes[i];
    const bool forward = p.guest >= g.begin && p.guest < g.end;
    const Body& own = forward ? g : hb;
    const Body& other = forward ? hb : g;
    W(i) = forward ? 0 : 1;
    Nd(i) = own.scene_index(p.guest - own.begin);
    for (int j = 0; j < 3; ++j) {
      H(i, j) = j < p.count ? other.scene_index(p.hosts[j] - other.begin) : -1;
      Wt(i, j) = j < p.count ? p.weight[j] : 0.0;
      D(i, j) = p.n[j];
    }
    Dp(i) = p.depth;
  }
  pyb::dict c;
  c["pair"] = label, c["h"] = h;
  c["way"] = way, c["node"] = node, c["hosts"] = hosts, c["weights"] = weights, c["direction"] = dir, c["depth"] = depth;
  return c;
}

// The callable's forces for one body: an (n, 3) array (or None: no force), added into f.
void add_body_forces(const pyb::handle& r, const World& w, int bi, Points& f, const std::string& what) {
  if (r.is_none()) return;
  const Body& b = w.bodies[bi];
  pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast> a;
  try {
    a = pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>::ensure(r);
  } catch (const pyb::error_already_set&) {
    a = {};
  }
  if (!a || a.ndim() != 2 || a.shape(0) != b.size() || a.shape(1) != 3)
    throw pyb::value_error(what + ": expected the forces on body " + b.name + " as an array of shape (" +
                           std::to_string(b.size()) + ", 3) or None");
  auto F = a.unchecked<2>();
  for (int q = 0; q < b.size(); ++q) {
    const Vec3 fq(F(q, 0), F(q, 1), F(q, 2));
    if (!fq.allFinite()) throw pyb::value_error(what + ": the force on node " + std::to_string(q) + " of body " + b.name + " is not finite");
    f[b.begin + b.local_of_scene(q)] += fq;
  }
}

std::string callable_name(const pyb::handle& fn) {
  for (const char* attr : {"__qualname__", "__name__"})
    if (pyb::hasattr(fn, attr)) return "python:" + pyb::str(fn.attr(attr)).cast<std::string>();
  return "python:" + pyb::str(pyb::type::handle_of(fn).attr("__name__")).cast<std::string>();
}

OwnResponse one(const pyb::object& fn, const ContactPairSpec& cp, const std::shared_ptr<PyResponses::Error>& error) {
  if (!PyCallable_Check(fn.ptr())) throw pyb::type_error("response for pair " + cp.label + ": expected a callable");
  auto held = std::make_shared<Held>(fn);
  const ContactSpec spec = cp.spec;
  const std::string label = cp.label;
  OwnResponse r;
  r.name = callable_name(fn);
  r.force = [held, spec, label, error](const World& w, const std::vector<Push>& pushes, double h, Points& f) {
    pyb::gil_scoped_acquire acquire;
    const std::string what = "response " + pyb::str(held->fn).cast<std::string>().substr(0, 60) + " (pair " + label + ")";
    try {
      pyb::object out = held->fn(contact_columns(w, spec, pushes, h, label), body_state(w, spec.guest), body_state(w, spec.host));
      if (!pyb::isinstance<pyb::tuple>(out) && !pyb::isinstance<pyb::list>(out))
        throw pyb::type_error(what + ": expected (forces on the guest, forces on the host), got " +
                              pyb::str(pyb::type::handle_of(out).attr("__name__")).cast<std::string>());
      pyb::sequence seq = out;
      if (seq.size() != 2) throw pyb::type_error(what + ": expected two arrays (guest, host)");
      add_body_forces(seq[0], w, spec.guest, f, what);
      add_body_forces(seq[1], w, spec.host, f, what);
    } catch (pyb::error_already_set& e) {
      if (!error->value) error->value = std::make_shared<pyb::error_already_set>(std::move(e));
      throw std::runtime_error(what + " raised an exception");
    } catch (const pyb::builtin_exception& e) {
      if (!error->value) {
        e.set_error();
        error->value = std::make_shared<pyb::error_already_set>();
      }
      throw std::runtime_error(what + ": " + e.what());
    }
  };
  return r;
}

}  // namespace

void PyResponses::raise_if_any() {
  if (!error || !error->value) return;
  const std::shared_ptr<pyb::error_already_set> e = std::move(error->value);
  error->value.reset();
  throw pyb::error_already_set(*e);
}

PyResponses python_responses(const pyb::object& response, const Scene& scene) {
  PyResponses out;
  out.error = std::make_shared<PyResponses::Error>();
  if (response.is_none()) return out;
  out.list.resize(scene.contacts.size());
  if (pyb::isinstance<pyb::dict>(response)) {
    for (const auto& [k, fn] : pyb::reinterpret_borrow<pyb::dict>(response)) {
      std::size_t i = scene.contacts.size();
      if (pyb::isinstance<pyb::str>(k)) {
        const std::string label = pyb::str(k);
        for (std::size_t p = 0; p < scene.contacts.size(); ++p)
          if (scene.contacts[p].label == label) i = p;
        if (i == scene.contacts.size()) throw pyb::key_error("response: no contact pair labelled '" + label + "'");
      } else {
        const long long idx = k.cast<long long>();
        if (idx < 0 || idx >= static_cast<long long>(scene.contacts.size()))
          throw pyb::index_error("response: pair " + std::to_string(idx) + ": the scene has " +
                                 std::to_string(scene.contacts.size()) + " contact pairs");
        i = static_cast<std::size_t>(idx);
      }
      out.list[i] = one(pyb::reinterpret_borrow<pyb::object>(fn), scene.contacts[i], out.error);
    }
    return out;
  }
  if (scene.contacts.empty()) throw pyb::value_error("response: the scene has no contact pairs");
  for (std::size_t p = 0; p < scene.contacts.size(); ++p) out.list[p] = one(response, scene.contacts[p], out.error);
  return out;
}

}  // namespace harness::py
