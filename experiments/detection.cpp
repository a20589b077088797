#include "experiments/detection.hpp"
#include "experiments/bench.hpp"

#include "core/clock.hpp"
#include "core/collision/collision.hpp"
#include "core/parallel.hpp"
#include "core/run/machine.hpp"
#include "core/run/signals.hpp"
#include "core/simulation.hpp"

#ifdef HARNESS_HAVE_REFERENCE
#include "reference/reference.hpp"
#endif

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace harness {

const std::vector<std::string>& detection_columns() {
  static const std::vector<std::string> c = {
      "source", "kind", "nodes", "host_nodes", "guest_nodes", "pair", "detector", "setting", "voxel_mm", "states",
      "rounds", "threads", "detect_us", "detect_min_us", "detect_max_us", "detect_warm_us", "detect_warm_min_us",
      "detect_warm_max_us", "true_pen_guest", "tp", "fp", "fn",
      "recall", "precision", "true_pen_host", "tp_host", "fp_host", "fn_host", "recall_host", "precision_host",
      "beyond_band", "device", "machine"};
  return c;
}

#ifndef HARNESS_HAVE_REFERENCE

int run_detection(const DetectionOptions&) {
  throw std::runtime_error("harness detection: this program was built without the reference library (CGAL's exact "
                           "sets are the truth it scores against)");
}

#else

namespace {

// SIGINT or SIGTERM: the command stops between two states, removes its unfinished CSV and exits
// 128 + the signal.
struct Interrupted {
  int signal;
};

void check_stop() {
  if (const int s = stop_signal()) throw Interrupted{s};
}

// One detector of the comparison: its one-sided Collision (timed) and its two-sided one (scored).
struct Candidate {
  std::string detector, setting;
  std::unique_ptr<Collision> timed, scored;
  std::vector<double> round_us, warm_us;  // per round: mean over the states of the first and the repeated call
  long long tp = 0, fp = 0, tp_host = 0, fp_host = 0;
  long long beyond = 0;
  bool has_band = false;
};

// Node-by-node scoring of reported nodes against a body's truth (each node once per state).
struct Scorer {
  std::vector<int> seen;
  int stamp = 0;
  void score(const std::vector<Contact>& found, const Body& b, const std::vector<std::uint8_t>& truth, long long& tp,
             long long& fp) {
    if (seen.size() != static_cast<std::size_t>(b.size())) seen.assign(b.size(), 0);
    ++stamp;
    for (const Contact& c : found) {
      const int li = c.guest - b.begin;
      if (li < 0 || li >= b.size()) {
        ++fp;
        continue;
      }
      if (seen[li] == stamp) continue;
      seen[li] = stamp;
      (truth[li] ? tp : fp) += 1;
    }
  }
};

std::vector<std::uint8_t> truth_of(const std::vector<Contact>& found, const Body& b) {
  std::vector<std::uint8_t> t(b.size(), 0);
  for (const Contact& c : found)
    if (c.guest >= b.begin && c.guest < b.end) t[c.guest - b.begin] = 1;
  return t;
}

// A two-sided pair's detection this way round and the other (Collision::detect is this way only).
void both_ways(Collision& c, const World& w) {
  c.detect_ahead(w, 0);
  c.detect_ahead(w, 1);
}

std::string ratio_text(long long a, long long b) {
  if (b <= 0) return "";
  char s[32];
  std::snprintf(s, sizeof s, "%.6g", static_cast<double>(a) / static_cast<double>(b));
  return s;
}

std::string csv_quoted(const std::string& s) {
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

class Source {
 public:
  Source(std::string label, std::string kind, long long nodes, const Scene& scene, const DetectionOptions& o)
      : label_(std::move(label)), kind_(std::move(kind)), nodes_(nodes), opt_(o) {
    SimulationOptions so;
    so.exact_detectors = make_exact_detector;
    so.audit = false;
    sim_ = std::make_unique<Simulation>(scene, so);
  }

  // The states: the initial one (bench) or K over the scene's steps (run as written).
  void collect(bool run) {
    World& w = sim_->world();
    if (!run) {
      states_.push_back(w.x);
      return;
    }
    const int steps = sim_->scene().steps, K = std::max(1, std::min(opt_.states, std::max(1, steps)));
    int next = 1;
    for (int k = 1; k <= K; ++k) {
      const int at = static_cast<int>(static_cast<long long>(k) * steps / K);
      for (; next <= at; ++next) sim_->step();
      check_stop();
      states_.push_back(w.x);
    }
    if (opt_.progress)
      std::fprintf(stderr, "detection: %s: %zu states over %d steps\n", label_.c_str(), states_.size(), steps);
  }

  void write(std::FILE* out) {
    const Scene& scene = sim_->scene();
    for (std::size_t pi = 0; pi < scene.contacts.size(); ++pi) {
      // The candidates are configured on the rest state, as a run configures them.
      World& w = sim_->world();
      const Points now = w.x;
      std::copy(rest_.begin(), rest_.end(), w.x.begin());
      std::vector<Candidate> cs = candidates(scene.contacts[pi].spec);
      std::copy(now.begin(), now.end(), w.x.begin());
      time(cs);
      score(cs, scene.contacts[pi].spec);
      emit(out, cs, scene.contacts[pi].label);
    }
  }

  void keep_rest() { rest_ = sim_->world().x; }

 private:
  std::vector<Candidate> candidates(const ContactSpec& pair) {
    const World& w = sim_->world();
    std::vector<Candidate> cs;
    auto add = [&](ContactSpec s, const std::string& setting) {
      Candidate c;
      c.detector = s.detector;
      c.setting = setting;
      s.two_sided = false;
      c.timed = std::make_unique<Collision>(w, s, make_exact_detector);
      s.two_sided = true;
      c.scored = std::make_unique<Collision>(w, s, make_exact_detector);
      cs.push_back(std::move(c));
    };
    ContactSpec s = pair;
    s.detector = "voxel";
    add(s, "the pair's voxel size");
    const double v = cs.back().timed->voxel_size();
    s.voxel_size = 0.5 * v;
    add(s, "voxel x0.5");
    s.voxel_size = 2.0 * v;
    add(s, "voxel x2");
    s = pair;
    s.detector = "voxel_exact";
    s.voxel_size = 0.0;
    add(s, "automatic voxel");
    s = pair;
    s.detector = "box";
    add(s, "the host's bounding box (the baseline)");
    s = pair;
    s.detector = "hash";
    s.cell_size = 0.0;
    add(s, "automatic cell");
    for (double f : opt_.hash_cells) {  // the cell sweep (--hash-cells)
      s.cell_size = f * current_surface_edge(w, pair.host);
      char label[64];
      std::snprintf(label, sizeof label, "cell x%g", f);
      add(s, label);
    }
    s = pair;
    s.detector = "fcl";
    add(s, "triangle pairs (AABB tree)");
    s.detector = "cgal";
    add(s, "inside test (the truth)");
    return cs;
  }

  void load(std::size_t k) {
    World& w = sim_->world();
    std::copy(states_[k].begin(), states_[k].end(), w.x.begin());
  }

  void time(std::vector<Candidate>& cs) {
    set_threads(1);
    const World& w = sim_->world();
    const std::size_t D = cs.size(), S = states_.size();
    const auto start = Clock::now();
    for (int r = 0; r < 100000; ++r) {
      if (r >= opt_.min_rounds && us_since(start) >= 1e6 * opt_.min_seconds) break;
      std::vector<double> sum(D, 0.0), warm(D, 0.0);
      for (std::size_t k = 0; k < S; ++k) {
        check_stop();
        load(k);
        for (std::size_t j = 0; j < D; ++j) {
          const std::size_t d = (j + static_cast<std::size_t>(r)) % D;
          auto t0 = Clock::now();
          cs[d].timed->detect(w);
          sum[d] += us_since(t0);
          t0 = Clock::now();  // the same state again at once: warm caches, fresh seeds
          cs[d].timed->detect(w);
          warm[d] += us_since(t0);
        }
      }
      for (std::size_t d = 0; d < D; ++d) {
        cs[d].round_us.push_back(sum[d] / static_cast<double>(S));
        cs[d].warm_us.push_back(warm[d] / static_cast<double>(S));
      }
    }
  }

  void score(std::vector<Candidate>& cs, const ContactSpec& pair) {
    const World& w = sim_->world();
    const Body& guest = w.bodies[pair.guest];
    const Body& host = w.bodies[pair.host];
    Candidate& truth = cs.back();  // cgal
    Scorer sg, sh;
    for (std::size_t k = 0; k < states_.size(); ++k) {
      check_stop();
      load(k);
      both_ways(*truth.scored, w);
      const std::vector<std::uint8_t> tg = truth_of(truth.scored->contacts(), guest);
      const std::vector<std::uint8_t> th = truth_of(truth.scored->reverse_contacts(), host);
      for (std::uint8_t b : tg) pen_guest_ += b;
      for (std::uint8_t b : th) pen_host_ += b;
      for (Candidate& c : cs) {
        if (&c != &truth) both_ways(*c.scored, w);
        sg.score(c.scored->contacts(), guest, tg, c.tp, c.fp);
        sh.score(c.scored->reverse_contacts(), host, th, c.tp_host, c.fp_host);
        const int band = c.scored->detector().beyond_band();
        if (band >= 0) c.has_band = true, c.beyond += band;
      }
    }
    guest_nodes_ = guest.size(), host_nodes_ = host.size();
  }

  void emit(std::FILE* out, const std::vector<Candidate>& cs, const std::string& pair) {
    const std::string machine = machine_string();
    for (const Candidate& c : cs) {
      const double med = median_of(c.round_us);
      const double lo = *std::min_element(c.round_us.begin(), c.round_us.end());
      const double hi = *std::max_element(c.round_us.begin(), c.round_us.end());
      const double wmed = median_of(c.warm_us);
      const double wlo = *std::min_element(c.warm_us.begin(), c.warm_us.end());
      const double whi = *std::max_element(c.warm_us.begin(), c.warm_us.end());
      const double vox = c.timed->voxel_size();
      std::fprintf(out, "%s,%s,%lld,%d,%d,%s,%s,%s,%s,%zu,%zu,1,%.4g,%.4g,%.4g,%.4g,%.4g,%.4g,%lld,%lld,%lld,%lld,%s,%s,%lld,%lld,%lld,"
                   "%lld,%s,%s,%s,cpu,%s\n",
                   csv_quoted(label_).c_str(), kind_.c_str(), nodes_ > 0 ? nodes_ : static_cast<long long>(sim_->world().num_nodes()), host_nodes_, guest_nodes_, csv_quoted(pair).c_str(),
                   c.detector.c_str(), csv_quoted(c.setting).c_str(), vox > 0 ? std::to_string(1e3 * vox).c_str() : "",
                   states_.size(), c.round_us.size(), med, lo, hi, wmed, wlo, whi, pen_guest_, c.tp, c.fp, pen_guest_ - c.tp,
                   ratio_text(c.tp, pen_guest_).c_str(), ratio_text(c.tp, c.tp + c.fp).c_str(), pen_host_, c.tp_host,
                   c.fp_host, pen_host_ - c.tp_host, ratio_text(c.tp_host, pen_host_).c_str(),
                   ratio_text(c.tp_host, c.tp_host + c.fp_host).c_str(),
                   c.has_band ? std::to_string(c.beyond).c_str() : "", csv_quoted(machine).c_str());
      if (opt_.progress)
        std::fprintf(stderr, "detection: %-24s %-12s %-28s %10.2f us  recall %s / %s  precision %s\n", label_.c_str(),
                     c.detector.c_str(), c.setting.c_str(), med, ratio_text(c.tp, pen_guest_).c_str(),
                     ratio_text(c.tp_host, pen_host_).c_str(), ratio_text(c.tp, c.tp + c.fp).c_str());
    }
    std::fflush(out);
  }

  std::string label_, kind_;
  long long nodes_;
  const DetectionOptions& opt_;
  std::unique_ptr<Simulation> sim_;
  Points rest_;
  std::vector<Points> states_;
  long long pen_guest_ = 0, pen_host_ = 0;
  int guest_nodes_ = 0, host_nodes_ = 0;
};

}  // namespace

int run_detection(const DetectionOptions& o) {
  const std::string tmp = o.out + ".tmp";
  std::FILE* out = std::fopen(tmp.c_str(), "w");
  if (!out) throw std::runtime_error("cannot write " + tmp);
  const auto& cols = detection_columns();
  for (std::size_t i = 0; i < cols.size(); ++i) std::fprintf(out, "%s%s", i ? "," : "", cols[i].c_str());
  std::fprintf(out, "\n");
  const int threads_before = threads();
  const StopSignals signals;
  try {
    for (const auto& [label, scene] : o.scenes) {
      if (scene.contacts.empty()) throw InputError(scene.file, "contacts: the scene has no contact pair to detect");
      Source s(label, "scene", 0, scene, o);
      s.keep_rest();
      s.collect(true);
      s.write(out);
    }
    for (long long n : o.sizes) {
      Source s("bench_" + std::to_string(n), "bench", n, make_bench_scene(n), o);
      s.keep_rest();
      s.collect(false);
      s.write(out);
    }
  } catch (const Interrupted& s) {
    std::fclose(out);
    std::remove(tmp.c_str());
    set_threads(threads_before);
    std::fprintf(stderr, "harness: detection interrupted (signal %d): %s not written\n", s.signal, o.out.c_str());
    return 128 + s.signal;
  } catch (...) {
    std::fclose(out);
    std::remove(tmp.c_str());
    set_threads(threads_before);
    throw;
  }
  set_threads(threads_before);
  const bool ok = std::ferror(out) == 0;
  if (std::fclose(out) != 0 || !ok) throw std::runtime_error("cannot write " + tmp);
  std::filesystem::rename(tmp, o.out);
  return 0;
}

#endif

}  // namespace harness
