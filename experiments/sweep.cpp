#include "experiments/sweep.hpp"

#include "core/run/summary_keys.hpp"
#include "core/scene/scene.hpp"

#include <nlohmann/json.hpp>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

extern char** environ;

namespace harness {

namespace fs = std::filesystem;
using nlohmann::json;

std::vector<std::pair<std::string, std::vector<std::string>>> parse_grids(const std::vector<std::string>& grids) {
  std::vector<std::pair<std::string, std::vector<std::string>>> out;
  for (const std::string& g : grids) {
    const auto eq = g.find('=');
    if (eq == std::string::npos || eq == 0) throw InputError("--grid " + g, "expected KEY=V1,V2,...");
    const std::string key = g.substr(0, eq), rest = g.substr(eq + 1);
    std::vector<std::string> values;
    std::string cur;
    int depth = 0;
    bool quoted = false;
    for (std::size_t i = 0; i < rest.size(); ++i) {
      const char c = rest[i];
      if (quoted) {
        cur += c;
        if (c == '\\' && i + 1 < rest.size()) cur += rest[++i];
        else if (c == '"') quoted = false;
        continue;
      }
      if (c == '"') quoted = true;
      if (c == '[' || c == '{') ++depth;
      if (c == ']' || c == '}') --depth;
      if (c == ',' && depth == 0) {
        values.push_back(cur);
        cur.clear();
      } else {
        cur += c;
      }
    }
    values.push_back(cur);
    for (std::string& v : values) {
      if (v.empty()) throw InputError("--grid " + key, "empty value in the list");
      try {
        const json parsed = json::parse(v);
        (void)parsed;
      } catch (const json::exception&) {
        // A bare word (auto, plane) is taken as a JSON string, so shells need no extra quotes.
        bool word = std::isalpha(static_cast<unsigned char>(v[0])) || v[0] == '_';
        for (char c : v) word = word && (std::isalnum(static_cast<unsigned char>(c)) || c == '_');
        if (!word) throw InputError("--grid " + key, "value is not valid JSON (" + v + ")");
        v = "\"" + v + "\"";
      }
    }
    for (const auto& [k, vs] : out)
      if (k == key) throw InputError("--grid " + key, "key given twice");
    out.emplace_back(key, values);
  }
  return out;
}

std::vector<SweepPoint> expand_grid(const std::vector<std::pair<std::string, std::vector<std::string>>>& g) {
  std::vector<SweepPoint> points(1);
  for (const auto& [key, values] : g) {
    std::vector<SweepPoint> next;
    for (const SweepPoint& p : points)
      for (const std::string& v : values) {
        SweepPoint q = p;
        q.emplace_back(key, v);
        next.push_back(std::move(q));
      }
    points = std::move(next);
  }
  return points;
}

namespace {
// A value as shown to people: JSON strings without their quotes.
std::string plain(const std::string& v) {
  if (v.size() >= 2 && v.front() == '"' && v.back() == '"') {
    try {
      return json::parse(v).get<std::string>();
    } catch (const json::exception&) {
    }
  }
  return v;
}
}  // namespace

std::string point_name(const SweepPoint& p) {
  std::string name;
  for (const auto& [k, v] : p) {
    if (!name.empty()) name += "__";
    name += k + "-" + plain(v);
  }
  for (char& c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_')) c = '_';
  return name.empty() ? "default" : name;
}

namespace {

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::vector<std::string> run_args(const SweepOptions& opt, const SweepJob& job, const std::string& scene) {
  std::vector<std::string> a = {opt.self, "run", scene, "--out", (fs::path(opt.out_dir) / job.name).string()};
  if (opt.max_wall > 0.0) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", opt.max_wall);
    a.insert(a.end(), {"--max-wall", b});
  }
  for (const std::string& s : opt.sets) a.insert(a.end(), {"--set", s});
  for (const auto& [k, v] : job.sets) a.insert(a.end(), {"--set", k + "=" + v});
  if (!opt.compare.empty()) a.insert(a.end(), {"--compare", opt.compare});
  return a;
}

pid_t spawn(const std::vector<std::string>& args, const std::string& log) {
  std::vector<char*> argv;
  for (const std::string& s : args) argv.push_back(const_cast<char*>(s.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) throw std::runtime_error("cannot start " + args[0]);
  return pid;
}

std::string csv_field(const json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) {
    std::string s = v.get<std::string>();
    if (s.find_first_of(",\"\n") != std::string::npos) {
      std::string q = "\"";
      for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
      return q + "\"";
    }
    return s;
  }
  if (v.is_boolean()) return v.get<bool>() ? "1" : "0";
  if (v.is_number_integer()) return std::to_string(v.get<long long>());
  if (v.is_number()) {
    char b[32];
    std::snprintf(b, sizeof b, "%.9g", v.get<double>());
    return b;
  }
  return csv_field(json(v.dump()));
}

}  // namespace

// The summary figures of runs.csv: column name and JSON pointer into summary.json (key paths from
// core/run/summary_keys.hpp; the first pair's figures under /pairs/0). A new figure is one line.
const std::vector<std::pair<std::string, std::string>>& merged_figures() {
  namespace k = summary_key;
  auto pair0 = [](const char* key) { return k::pair_key(0, key); };
  auto under = [](const char* parent, const char* key) { return std::string(parent) + "/" + key; };
  auto error = [&](int i) { return pair0(k::kErrorVsReference) + "/" + k::kErrorFigures[i]; };
  auto error_window = [&](const char* stat) { return pair0(k::kErrorVsReference) + k::kErrorWindow + "/" + stat; };
  static const std::vector<std::pair<std::string, std::string>> figures = {
      {"status", k::kStatus},
      {"stability", k::kStabilityVerdict},
      {"contact_power_ratio", under(k::kWindow, k::kContactPowerRatio)},
      {"steps_run", k::kSteps},
      {"finite", k::kFinite},
      {"state_hash", k::kStateHash},
      {"kinetic_energy_final", k::kKineticFinal},
      {"kinetic_energy_peak", k::kKineticPeak},
      {"substeps", k::kMaxSubsteps},
      {"guard_violations", k::kGuardViolations},
      {"t_step_us", under(k::kTiming, k::kTimingParts[0])},
      {"t_physics_us", under(k::kTiming, k::kTimingParts[1])},
      {"t_detect_us", under(k::kTiming, k::kTimingParts[2])},
      {"t_eliminate_us", under(k::kTiming, k::kTimingParts[3])},
      {"t_cgal_us", under(k::kTiming, k::kTimingParts[4])},
      {"t_fcl_us", under(k::kTiming, k::kTimingParts[5])},
      {"voxel_size_used", pair0(k::kVoxelSizeUsed)},
      {"region_rebuilds", pair0(k::kRegionRebuilds)},
      {"contacts_total", pair0(k::kContactsTotal)},
      {"true_pen_final", pair0(k::kTruePenFinal)},
      {"max_depth_final", pair0(k::kMaxDepthFinal)},
      {"max_depth_peak", pair0(k::kMaxDepthPeak)},
      {"recall", pair0(k::kRecall)},
      {"precision", pair0(k::kPrecision)},
      {"tunnelled_guest", pair0(k::kTunnelled)},
      {"tunnelled_host", pair0(k::kTunnelledHost)},
      {"settled", k::kSettled},
      {"residual", k::kResidual},
      {"settle_steps", k::kSettleSteps},
      {"work_external", under(k::kEnergy, k::kWorkExternal)},
      {"energy_dissipated", under(k::kEnergy, k::kDissipated)},
      {"work_contact", under(k::kEnergy, k::kWorkContact)},
      {"work_contact_peak", under(k::kEnergy, k::kWorkContactPeak)},
      {"energy_balance_error", under(k::kEnergy, k::kBalanceError)},
      {"pos_err_max", error(0)},
      {"pos_err_rms", error(1)},
      {"gap_max", error(2)},
      {"gap_mean", error(3)},
      {"depth_max", error(4)},
      {"error_window_mean", error_window("mean")},
      {"error_window_max", error_window("max")},
      {"error_window_chatter", error_window("amplitude")},
      {"depth_window_max", pair0(k::kErrorVsReference) + k::kDepthWindow + "/max"},
      {"reference_converged", k::kCompareConverged},
  };
  return figures;
}

namespace {

// A number at a pointer of a summary, or NaN.
double number_at(const json& s, const std::string& ptr) {
  const json::json_pointer jp(ptr);
  return s.contains(jp) && s.at(jp).is_number() ? s.at(jp).get<double>() : std::nan("");
}

// The columns runs.csv adds after the figures, from a run's summary and its no-force run's (null:
// none): the no-force run's window error, "helps", and what makes a stable run useless.
std::vector<json> judged_columns(const json& s, const json* base) {
  namespace k = summary_key;
  const std::string ev = k::pair_key(0, k::kErrorVsReference);
  // The figures the studies' rule reads: the window's mean error and its deepest penetration.
  auto error = [&](const json* x) { return x ? number_at(*x, ev + k::kErrorWindow + "/mean") : std::nan(""); };
  auto deepest = [&](const json* x) { return x ? number_at(*x, ev + k::kDepthWindow + "/max") : std::nan(""); };
  const double err = error(&s), depth = deepest(&s), base_err = error(base), base_depth = deepest(base);
  const double tunnelled = number_at(s, k::pair_key(0, k::kTunnelled)) + number_at(s, k::pair_key(0, k::kTunnelledHost));
  json helps;  // null: not judged (no no-force run, or no error: run without --compare)
  if (std::isfinite(err) && std::isfinite(base_err))
    helps = err <= kHelpsShare * base_err ||
                    (std::isfinite(depth) && std::isfinite(base_depth) && depth <= kHelpsShare * base_depth && err <= base_err)
                ? "yes" : "no";
  std::string useless;
  if (tunnelled > 0) useless = "tunnels";
  if (helps == "no") useless += std::string(useless.empty() ? "" : "; ") + "no better than no force";
  return {std::isfinite(base_err) ? json(base_err) : json(), helps, useless.empty() ? json() : json(useless)};
}

json read_summary(const fs::path& sp) {
  if (!fs::exists(sp)) return json();
  try {
    std::ifstream in(sp);
    return json::parse(in);
  } catch (const json::exception&) {
    return json();
  }
}

}  // namespace

std::vector<SweepJob> sweep_jobs(const std::vector<SweepPoint>& points, bool baseline, std::size_t pairs) {
  std::vector<SweepJob> jobs;
  for (const SweepPoint& p : points) jobs.push_back({p, point_name(p), -1, false});
  if (!baseline) return jobs;
  std::map<std::string, int> made;  // name of the point's values outside contacts.* -> its job
  for (std::size_t i = 0; i < points.size(); ++i) {
    SweepPoint rest, sets;
    for (const auto& kv : points[i])
      if (kv.first.rfind("contacts.", 0) != 0) rest.push_back(kv);
    const std::string name = rest.empty() ? "no_force" : "no_force__" + point_name(rest);
    auto it = made.find(name);
    if (it == made.end()) {
      sets = rest;
      for (std::size_t c = 0; c < pairs; ++c) sets.emplace_back("contacts." + std::to_string(c) + ".force", "0");
      it = made.emplace(name, static_cast<int>(jobs.size())).first;
      jobs.push_back({sets, name, -1, true});
    }
    jobs[i].baseline = it->second;
  }
  return jobs;
}

void merge_runs(const std::string& out_dir, const std::vector<SweepPoint>& points, const std::vector<SweepJob>& jobs) {
  // Unique temporary name: several --index runs (one per scheduler task) may merge at once.
  const fs::path tmp = fs::path(out_dir) / ("runs.csv.tmp." + std::to_string(::getpid()));
  std::ofstream o(tmp);
  o << "point,name,no_force";
  if (!points.empty())
    for (const auto& [k, v] : points[0]) o << "," << csv_field(json(k));
  for (const auto& [name, ptr] : merged_figures()) o << "," << name;
  o << ",no_force_error,helps,useless\n";
  std::vector<json> sums;
  for (const SweepJob& j : jobs) sums.push_back(read_summary(fs::path(out_dir) / j.name / "summary.json"));
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const json& s = sums[i];
    if (s.is_null()) continue;
    o << i << "," << csv_field(json(jobs[i].name)) << "," << (jobs[i].no_force ? 1 : 0);
    if (!points.empty())
      for (const auto& [k, v] : points[0]) {  // a no-force run: its values outside contacts.*
        std::string val;
        for (const auto& [jk, jv] : jobs[i].no_force ? jobs[i].sets : points[i])
          if (jk == k) val = plain(jv);
        o << "," << csv_field(json(val));
      }
    for (const auto& [name, ptr] : merged_figures()) {
      const json::json_pointer jp(ptr);
      o << "," << csv_field(s.contains(jp) ? s.at(jp) : json());
    }
    const json* base = jobs[i].baseline >= 0 && !sums[jobs[i].baseline].is_null() ? &sums[jobs[i].baseline] : nullptr;
    for (const json& c : judged_columns(s, jobs[i].no_force ? nullptr : base)) o << "," << csv_field(c);
    o << "\n";
  }
  o.close();
  if (!o) throw std::runtime_error("cannot write " + tmp.string());
  fs::rename(tmp, fs::path(out_dir) / "runs.csv");
}

int run_sweep(const SweepOptions& opt) {
  const auto grids = parse_grids(opt.grids);
  if (grids.empty()) throw InputError("--grid", "at least one --grid KEY=V1,V2,... is needed");
  const std::vector<SweepPoint> points = expand_grid(grids);
  // Every point is validated before anything runs: a bad key or value is bad input now.
  std::vector<std::pair<std::string, std::string>> fixed;
  for (const std::string& s : opt.sets) {
    const auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0) throw InputError("--set " + s, "expected KEY=JSON");
    fixed.emplace_back(s.substr(0, eq), s.substr(eq + 1));
  }
  const std::string text = read_text_file(opt.scene);
  std::size_t pairs = 0;
  for (const SweepPoint& p : points) {
    auto ov = fixed;
    ov.insert(ov.end(), p.begin(), p.end());
    pairs = std::max(pairs, parse_scene(text, opt.scene, ov).contacts.size());
  }
  const std::vector<SweepJob> jobs = sweep_jobs(points, opt.baseline, pairs);
  if (opt.index >= static_cast<int>(jobs.size()))
    throw InputError("--index", "point " + std::to_string(opt.index) + " does not exist (" +
                                    std::to_string(jobs.size()) + " points, 0-based)");
  if (opt.merge) {
    merge_runs(opt.out_dir, points, jobs);
    return 0;
  }
  if (opt.list) {
    for (const SweepJob& j : jobs) {
      std::string line;
      std::vector<std::string> a = run_args(opt, j, opt.scene_arg);
      a[0] = "harness";
      for (const std::string& s : a) line += (line.empty() ? "" : " ") + (s.find_first_of(" '\"{}[],$*") != std::string::npos ? shell_quote(s) : s);
      std::printf("%s\n", line.c_str());
    }
    return 0;
  }
  fs::create_directories(opt.out_dir);
  std::vector<std::size_t> todo;
  if (opt.index >= 0) todo.push_back(static_cast<std::size_t>(opt.index));
  else
    for (std::size_t i = 0; i < jobs.size(); ++i) todo.push_back(i);

  std::map<pid_t, std::size_t> running;
  int worst = 0;
  std::size_t next = 0, done = 0;
  auto reap = [&]() {
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid <= 0) return;
    const std::size_t i = running[pid];
    running.erase(pid);
    ++done;
    const int rc = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    std::fprintf(stderr, "sweep: [%zu/%zu] %s: %s\n", done, todo.size(), jobs[i].name.c_str(),
                 rc == 0 ? "ok" : rc == 3 ? "simulation failed (exit 3)" : ("exit " + std::to_string(rc)).c_str());
    if (rc != 0 && rc != 3) worst = std::max(worst, 1);
    // The point's own log (POINT/stderr.log: progress every 10 %, the end-of-run line): all of it
    // for a single --index job (a scheduler's per-job log), else its last line.
    std::ifstream log(fs::path(opt.out_dir) / jobs[i].name / "stderr.log");
    std::string line, last;
    while (std::getline(log, line)) {
      if (opt.index >= 0) std::fprintf(stderr, "%s\n", line.c_str());
      last = line;
    }
    if (opt.index < 0 && !last.empty()) std::fprintf(stderr, "  %s\n", last.c_str());
  };
  while (next < todo.size() || !running.empty()) {
    while (next < todo.size() && static_cast<int>(running.size()) < std::max(1, opt.jobs)) {
      const std::size_t i = todo[next++];
      const fs::path dir = fs::path(opt.out_dir) / jobs[i].name;
      fs::create_directories(dir);
      running[spawn(run_args(opt, jobs[i], opt.scene), (dir / "stderr.log").string())] = i;
    }
    reap();
  }
  merge_runs(opt.out_dir, points, jobs);
  return worst;
}

}  // namespace harness
