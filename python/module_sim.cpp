// harness.Simulation: a scene built and stepped from Python. Positions and velocities are
// read-only numpy views of the simulation's own arrays (no copy; they follow every step); the GIL
// is released while stepping, and a signal (Ctrl-C) stops a long step(n) between two steps.
#include "python/module.hpp"

#include "core/clock.hpp"
#include "core/parallel.hpp"
#include "core/run/run_scene.hpp"
#include "core/node_order.hpp"
#include "core/simulation.hpp"

#ifdef HARNESS_HAVE_REFERENCE
#include "reference/reference.hpp"
#endif

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <atomic>
#include <memory>
#include <set>

namespace harness::py {

namespace {

// The simulation error: a step that failed (non-finite state, a region past its cap). The
// simulation keeps the last good state.
pyb::object& simulation_error() {
  static pyb::object* e = new pyb::object();  // never destroyed (after finalization)
  return *e;
}

// Sets the kernels' thread count for its lifetime, then puts the caller's back.
struct ThreadCount {
  explicit ThreadCount(int n) : before(threads()) { set_threads(n); }
  ~ThreadCount() { set_threads(before); }
  int before;
};

// An index given by Python (int, numpy integer; not bool), or nothing when `o` is not one.
bool as_index(const pyb::handle& o, long long& out) {
  if (PyBool_Check(o.ptr()) || !PyIndex_Check(o.ptr())) return false;
  pyb::object i = pyb::reinterpret_steal<pyb::object>(PyNumber_Index(o.ptr()));
  if (!i) throw pyb::error_already_set();
  int overflow = 0;
  out = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
  if (overflow) out = overflow > 0 ? std::numeric_limits<long long>::max() : std::numeric_limits<long long>::min();
  return true;
}

class PySim {
 public:
  PySim(const pyb::object& scene, int threads, const std::string& node_order, const pyb::object& response)
      : threads_(threads) {
    if (threads < 1) throw pyb::value_error("threads: must be >= 1");
    SimulationOptions so;
    if (!parse_node_order(node_order, so.layout.order))
      throw pyb::value_error("node_order: expected scene, rcm or morton, not '" + node_order + "'");
    const PyScene s = as_scene(scene);
    so.exact_detectors = exact_detector_maker();
    so.user_forces = true;  // add_forces()
    responses_ = python_responses(response, s.scene);
    so.responses = responses_.list;
    sim_ = std::make_unique<Simulation>(s.scene, so);
    good_x_.resize(sim_->world().num_nodes());
    good_v_.resize(sim_->world().num_nodes());
  }

  // n steps with the run's checks (checked_step); between steps, at most every 20 ms, Python's
  // signal handlers run (Ctrl-C: KeyboardInterrupt after a whole step).
  void step(long long n) {
    if (n < 0) throw pyb::value_error("step: n must be >= 0");
    const Busy busy(*this);
    const ThreadCount tc(threads_);
    std::string failure;
    int failed = 0;
    {
      pyb::gil_scoped_release release;
      auto last_check = Clock::now();
      for (long long i = 0; i < n && failure.empty(); ++i) {
        failure = checked_step(*sim_, good_x_, good_v_);
        if (!failure.empty()) failed = sim_->step_index() + 1;
        if (i + 1 < n && us_since(last_check) > 20000.0) {
          last_check = Clock::now();
          check_signals();
        }
      }
    }
    if (!failure.empty()) {
      responses_.raise_if_any();  // a response's own exception, as it was raised
      const std::string msg = "step " + std::to_string(failed) + ": " + failure +
                              "; the simulation holds the last good state (step " + std::to_string(failed - 1) + ")";
      PyErr_SetString(simulation_error().ptr(), msg.c_str());
      throw pyb::error_already_set();
    }
  }

  // While one thread steps (the GIL released), every other call on the same simulation is refused.
  struct Busy {
    explicit Busy(const PySim& s) : sim(s) {
      if (sim.busy_.exchange(true))
        throw std::runtime_error("this Simulation is stepping in another thread (one simulation is stepped by one "
                                 "thread at a time; make one Simulation per thread)");
    }
    ~Busy() { sim.busy_ = false; }
    const PySim& sim;
  };

  const Body& body(const pyb::object& which) const {
    const World& w = sim_->world();
    long long i = 0;
    if (as_index(which, i)) {
      if (i < 0 || i >= static_cast<long long>(w.bodies.size()))
        throw pyb::index_error("body " + std::to_string(i) + ": the scene has " + std::to_string(w.bodies.size()));
      return w.bodies[static_cast<std::size_t>(i)];
    }
    if (!pyb::isinstance<pyb::str>(which)) throw pyb::type_error("a body is a name (str) or an index (int)");
    const std::string name = pyb::str(which);
    const int found = w.find_body(name);
    if (found < 0) throw pyb::key_error("no body named '" + name + "'");
    return w.bodies[found];
  }

  std::size_t pair(const pyb::object& which) const {
    const auto& pairs = sim_->pairs();
    long long i = 0;
    if (as_index(which, i)) {
      if (i < 0 || i >= static_cast<long long>(pairs.size()))
        throw pyb::index_error("pair " + std::to_string(i) + ": the scene has " + std::to_string(pairs.size()));
      return static_cast<std::size_t>(i);
    }
    if (!pyb::isinstance<pyb::str>(which)) throw pyb::type_error("a pair is a label (str) or an index (int)");
    const std::string label = pyb::str(which);
    for (std::size_t p = 0; p < pairs.size(); ++p)
      if (pairs[p].label == label) return p;
    throw pyb::key_error("no contact pair labelled '" + label + "'");
  }

  // A read-only (n, 3) view of a body's rows of x or v, kept alive by `self`.
  static pyb::array view(const pyb::object& self, const pyb::object& which, bool velocities) {
    PySim& s = self.cast<PySim&>();
    const Busy busy(s);
    const Body& b = s.body(which);
    Points& p = velocities ? s.sim_->world().v : s.sim_->world().x;
    if (!b.scene_node.empty()) {  // a world laid out in another order (node_order.hpp): a copy, rows in the scene's numbering
      pyb::array_t<double> c({static_cast<pyb::ssize_t>(b.size()), pyb::ssize_t{3}});
      auto m = c.mutable_unchecked<2>();
      for (int q = 0; q < b.size(); ++q)
        for (int k = 0; k < 3; ++k) m(q, k) = p[b.begin + b.local_of_scene(q)][k];
      pyb::detail::array_proxy(c.ptr())->flags &= ~pyb::detail::npy_api::NPY_ARRAY_WRITEABLE_;
      return std::move(c);
    }
    pyb::array a(pyb::dtype::of<double>(), {static_cast<pyb::ssize_t>(b.size()), pyb::ssize_t{3}},
                 {static_cast<pyb::ssize_t>(sizeof(Vec3)), static_cast<pyb::ssize_t>(sizeof(double))},
                 p[b.begin].data(), self);
    pyb::detail::array_proxy(a.ptr())->flags &= ~pyb::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    return a;
  }

  // Sets a body's positions (or velocities): all of them from an (n, 3) array, or those of the
  // body-local `nodes` from a (len(nodes), 3) one. The energy audit restarts from the new state.
  void set_rows(const pyb::object& which, const pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>& a,
                const pyb::object& nodes, bool velocities) {
    const Busy busy(*this);
    const Body& b = body(which);
    const std::vector<int> idx = node_list(b, nodes, true);
    const auto r = checked_rows(a, idx.size());
    World& w = sim_->world();
    Points& p = velocities ? w.v : w.x;
    double dE = 0.0;  // the kinetic energy's change (velocities)
    for (std::size_t k = 0; k < idx.size(); ++k) {
      const int i = b.begin + b.local_of_scene(idx[k]);
      const Vec3 now(r(k, 0), r(k, 1), r(k, 2));
      if (velocities) dE += 0.5 * w.m[i] * (now.squaredNorm() - p[i].squaredNorm());
      p[i] = now;
    }
    // Velocities: the kinetic energy's change is booked as external work (in proportion to the
    // nodes set); positions change the springs' energy: the audit restarts (a pass over them).
    if (velocities) sim_->book_kinetic_change(dE);
    else sim_->reset_energy();
  }

  // The body-local node indices `nodes` (None: all) in the scene's numbering, checked; `unique`:
  // a node given twice is refused.
  std::vector<int> node_list(const Body& b, const pyb::object& nodes, bool unique) const {
    std::vector<int> idx;
    if (nodes.is_none()) {
      idx.resize(static_cast<std::size_t>(b.size()));
      for (int i = 0; i < b.size(); ++i) idx[static_cast<std::size_t>(i)] = i;
      return idx;
    }
    if (!pyb::isinstance<pyb::iterable>(nodes) || pyb::isinstance<pyb::str>(nodes))
      throw pyb::type_error("nodes: a sequence of body-local node indices");
    std::set<int> seen;
    for (const pyb::handle& h : nodes) {
      long long i = 0;
      if (!as_index(h, i)) throw pyb::type_error("nodes: a sequence of body-local node indices");
      if (i < 0 || i >= b.size())
        throw pyb::index_error("node " + std::to_string(i) + ": body " + b.name + " has " + std::to_string(b.size()));
      if (unique && !seen.insert(static_cast<int>(i)).second)
        throw pyb::value_error("node " + std::to_string(i) + " given twice");
      idx.push_back(static_cast<int>(i));
    }
    return idx;
  }

  // The rows of an (n, 3) array of finite numbers (ValueError otherwise).
  static pyb::detail::unchecked_reference<double, 2> checked_rows(const pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>& a, std::size_t n) {
    if (a.ndim() != 2 || a.shape(1) != 3 || a.shape(0) != static_cast<pyb::ssize_t>(n))
      throw pyb::value_error("expected an array of shape (" + std::to_string(n) + ", 3)");
    auto r = a.unchecked<2>();
    for (std::size_t k = 0; k < n; ++k)
      if (!std::isfinite(r(k, 0)) || !std::isfinite(r(k, 1)) || !std::isfinite(r(k, 2)))
        throw pyb::value_error("row " + std::to_string(k) + " is not finite");
    return r;
  }

  // Forces (N) on a body's nodes (all, or the body-local `nodes`; a node given twice gets both) in
  // every substep of the next step only, booked by the energy audit as external work.
  void add_forces(const pyb::object& which, const pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>& a,
                  const pyb::object& nodes) {
    const Busy busy(*this);
    const Body& b = body(which);
    const std::vector<int> idx = node_list(b, nodes, false);
    const auto r = checked_rows(a, idx.size());
    for (std::size_t k = 0; k < idx.size(); ++k)
      sim_->add_next_force(b.begin + b.local_of_scene(idx[k]), Vec3(r(k, 0), r(k, 1), r(k, 2)));
  }

  // The body's node masses, kg, in the scene's numbering (a copy).
  pyb::array_t<double> masses(const pyb::object& which) const {
    const Busy busy(*this);
    const Body& b = body(which);
    pyb::array_t<double> m(static_cast<pyb::ssize_t>(b.size()));
    auto M = m.mutable_unchecked<1>();
    for (int q = 0; q < b.size(); ++q) M(q) = sim_->world().m[b.begin + b.local_of_scene(q)];
    return m;
  }

  pyb::dict contacts(const pyb::object& which) const;
  pyb::object measure(const pyb::object& which);
  pyb::dict energy() const;
  Simulation& sim() { return *sim_; }
  const Simulation& sim() const { return *sim_; }

 private:
  int threads_ = 1;
  std::unique_ptr<Simulation> sim_;
  Points good_x_, good_v_;
  std::vector<std::unique_ptr<Measurer>> measurers_;  // per pair, made on the first measure()
  PyResponses responses_;  // the pairs' Python responses (none: the scene's force rules)
  mutable std::atomic<bool> busy_{false};
};

template <typename T>
pyb::array_t<T> column(const std::vector<T>& v) {
  pyb::array_t<T> a(static_cast<pyb::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

// The last step's contacts of a pair, one row per contact: the penetrating node (body-local, in
// the guest's body; way 1: a host node inside the guest, two-sided), the detector's host key,
// the push's direction on that node, the depth the eliminator sees (m, negative outside) and the
// force (N; projection: 1 where it moved the node).
pyb::dict PySim::contacts(const pyb::object& which) const {
  const Busy busy(*this);
  const Pair& pr = sim_->pairs()[pair(which)];
  const World& w = sim_->world();
  std::vector<int> node, key, way;
  std::vector<double> depth, force;
  std::vector<double> dir;
  if (pr.collision && pr.collision->stepped()) {
    const Collision& c = *pr.collision;
    const auto& pushes = c.pushes();
    std::size_t k = 0;
    for (int side = 0; side < 2; ++side) {
      const Body& nb = w.bodies[side == 0 ? pr.spec.guest : pr.spec.host];
      for (const Contact& ct : side == 0 ? c.contacts() : c.reverse_contacts()) {
        node.push_back(nb.scene_index(ct.guest - nb.begin)), key.push_back(ct.key), way.push_back(side);
        const bool has = k < pushes.size();
        for (int d = 0; d < 3; ++d) dir.push_back(has ? pushes[k].n[d] : 0.0);
        depth.push_back(has ? pushes[k].depth : 0.0);
        force.push_back(k < c.magnitudes().size() ? c.magnitudes()[k] : 0.0);
        ++k;
      }
    }
  }
  pyb::dict out;
  out["node"] = column(node), out["key"] = column(key), out["way"] = column(way);
  pyb::array_t<double> d({static_cast<pyb::ssize_t>(node.size()), pyb::ssize_t{3}});
  std::copy(dir.begin(), dir.end(), d.mutable_data());
  out["direction"] = d, out["depth"] = column(depth), out["force"] = column(force);
  return out;
}

pyb::dict ledger(const EnergyLedger& e, const Simulation& sim) {
  pyb::dict d;
  d["kinetic"] = e.kinetic, d["elastic"] = e.elastic, d["potential"] = e.potential, d["initial"] = e.initial;
  d["work_external"] = e.work_external, d["dissipated"] = e.dissipated, d["work_contact"] = e.work_contact;
  d["work_contact_peak"] = e.work_contact_peak, d["balance_error"] = e.balance_error();
  d["residual"] = sim.residual();
  return d;
}

pyb::dict PySim::energy() const {
  const Busy busy(*this);
  return ledger(sim_->energy(), *sim_);
}

#ifdef HARNESS_HAVE_REFERENCE
pyb::dict measurement(const Measurement& m) {
  pyb::dict d;
  d["true_pen_guest"] = m.true_pen_guest, d["true_pen_host"] = m.true_pen_host;
  d["max_depth"] = m.max_depth, d["mean_depth"] = m.mean_depth;
  d["tp"] = m.tp, d["fp"] = m.fp, d["fn"] = m.fn;
  d["tp_host"] = m.tp_host, d["fp_host"] = m.fp_host, d["fn_host"] = m.fn_host;
  d["tunnelled_guest"] = m.tunnelled_guest, d["tunnelled_host"] = m.tunnelled_host;
  d["surfaces_intersect"] = m.surfaces_intersect;
  double gap = std::numeric_limits<double>::infinity();
  for (const auto* sd : {m.sd_guest, m.sd_host})
    if (sd)
      for (double x : *sd) gap = std::min(gap, x);
  d["gap"] = gap;
  d["fcl_pairs"] = m.fcl_pairs, d["fcl_max_depth"] = m.fcl_max_depth;
  d["t_cgal_us"] = m.t_cgal_us, d["t_fcl_us"] = m.t_fcl_us;
  return d;
}
#endif

// The exact references of the current state, per pair (CGAL and FCL; reference/measure_reference.hpp).
pyb::object PySim::measure(const pyb::object& which) {
#ifdef HARNESS_HAVE_REFERENCE
  const Busy busy(*this);
  const auto& pairs = sim_->pairs();
  measurers_.resize(pairs.size());
  pyb::list all;
  const std::size_t first = which.is_none() ? 0 : pair(which), last = which.is_none() ? pairs.size() : first + 1;
  for (std::size_t p = first; p < last; ++p) {
    ReferenceSpec rs;
    rs.cgal = rs.fcl = true;
    if (!measurers_[p]) measurers_[p] = make_reference_measurer(sim_->world(), pairs[p].spec, rs);
    static const std::vector<Contact> none;
    const Collision* c = pairs[p].collision.get();
    const bool stepped = c && c->stepped();
    Measurement m;
    measurers_[p]->measure(sim_->world(), pairs[p].spec, stepped ? c->contacts() : none,
                           stepped ? c->reverse_contacts() : none, m);
    pyb::dict d = measurement(m);
    d["pair"] = pairs[p].label;
    all.append(d);
  }
  if (!which.is_none()) return all[0];
  return std::move(all);
#else
  (void)which;
  throw pyb::type_error("measure(): this module was built without the reference library (FCL, CGAL)");
#endif
}

}  // namespace

void bind_simulation(pyb::module_& m) {
  simulation_error() = pyb::exception<std::runtime_error>(m, "SimulationError", PyExc_RuntimeError);
  pyb::class_<PySim>(m, "Simulation", "A scene built and stepped from Python (docs/python.md).")
      .def(pyb::init<const pyb::object&, int, const std::string&, const pyb::object&>(), pyb::arg("scene"),
           pyb::arg("threads") = 1, pyb::arg("node_order") = std::string(node_order_name(kDefaultNodeOrder)),
           pyb::arg("response") = pyb::none(),
           "A simulation of a Scene (or a dict, a scene file, a bundled name), built now (SceneError for bad input); "
           "node_order: the nodes' layout (scene, rcm, morton; arrays keep the scene's numbering); response: a "
           "contact response of your own instead of the scene's force rule (a callable for every pair, or a dict "
           "of pair label or index -> callable; docs/python.md): response(contacts, guest, host) -> "
           "(forces on the guest, forces on the host).")
      .def("step", &PySim::step, pyb::arg("n") = 1,
           "n steps of scene.dt (the GIL released; Ctrl-C stops between steps with KeyboardInterrupt).")
      .def_property_readonly("time", [](const PySim& s) { return s.sim().time(); })
      .def_property_readonly("step_index", [](const PySim& s) { return s.sim().step_index(); })
      .def_property_readonly("bodies", [](const PySim& s) {
        std::vector<std::string> n;
        for (const Body& b : s.sim().world().bodies) n.push_back(b.name);
        return n;
      })
      .def_property_readonly("pairs", [](const PySim& s) {
        std::vector<std::string> n;
        for (const Pair& p : s.sim().pairs()) n.push_back(p.label);
        return n;
      })
      .def("positions", [](const pyb::object& self, const pyb::object& body) { return PySim::view(self, body, false); },
           pyb::arg("body"), "A read-only (n, 3) view of the body's positions, m (no copy: it follows the steps; with a node_order other "
           "than the scene's, a read-only copy of them now, in the scene's numbering).")
      .def("velocities", [](const pyb::object& self, const pyb::object& body) { return PySim::view(self, body, true); },
           pyb::arg("body"), "A read-only (n, 3) view of the body's velocities, m/s.")
      .def("set_positions", [](PySim& s, const pyb::object& body, const pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>& a,
                               const pyb::object& nodes) { s.set_rows(body, a, nodes, false); },
           pyb::arg("body"), pyb::arg("array"), pyb::arg("nodes") = pyb::none(),
           "Sets the body's positions (all, or those of the body-local `nodes`); the energy audit restarts (a pass "
           "over the springs).")
      .def("set_velocities", [](PySim& s, const pyb::object& body, const pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>& a,
                                const pyb::object& nodes) { s.set_rows(body, a, nodes, true); },
           pyb::arg("body"), pyb::arg("array"), pyb::arg("nodes") = pyb::none(),
           "Sets the body's velocities (all, or those of the body-local `nodes`), in proportion to the nodes set; "
           "the kinetic energy's change is booked as external work.")
      .def("add_forces", &PySim::add_forces, pyb::arg("body"), pyb::arg("array"), pyb::arg("nodes") = pyb::none(),
           "Adds forces (N, shape (len(nodes), 3); nodes None: all the body's) to the next step only, in every "
           "substep; the energy audit books their work as external.")
      .def("masses", &PySim::masses, pyb::arg("body"), "The body's node masses, kg (a copy, in the scene's numbering).")
      .def("contacts", &PySim::contacts, pyb::arg("pair") = 0, "The last step's contacts of a pair (index or label).")
      .def("measure", &PySim::measure, pyb::arg("pair") = pyb::none(),
           "The exact references (CGAL, FCL) of the current state: one dict per pair, or the given pair's.")
      .def("energy", &PySim::energy, "The energy audit so far (J) and the force residual.")
      .def("state_hash", [](const PySim& s) {
        const PySim::Busy busy(s);
        return state_hash(s.sim().world());
      })
      .def("critical_dt", [](const PySim& s) { return s.sim().critical_dt(); })
      .def("last_times", [](const PySim& s) {
        const StepTimes& t = s.sim().last();
        pyb::dict d;
        d["step_us"] = t.step_us, d["physics_us"] = t.physics_us, d["detect_us"] = t.detect_us, d["eliminate_us"] = t.eliminate_us;
        return d;
      }, "Wall times of the last step, microseconds.");
}

}  // namespace harness::py
