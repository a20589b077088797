// `harness run --ensemble K` (run_scene.hpp, run_ensemble): the members, then what they share.
#include "core/run/run_scene.hpp"
#include "core/run/summary.hpp"
#include "core/run/summary_keys.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace harness {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json read_json(const fs::path& p) {
  std::ifstream in(p);
  if (!in) throw std::runtime_error("cannot read " + p.string());
  return json::parse(in);
}

// The numbers of a summary the ensemble summarises, by JSON pointer: every number under `window`
// and `pairs` (thresholds and limits aside: they are constants), and a few top-level figures.
void numbers(const json& j, const std::string& at, std::map<std::string, double>& out) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      const std::string& k = it.key();
      if (k == "thresholds" || k.find("limit") != std::string::npos || k == "dir") continue;
      numbers(it.value(), at + "/" + k, out);
    }
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) numbers(j[i], at + "/" + std::to_string(i), out);
  } else if (j.is_number()) {
    out[at] = j.get<double>();
  } else if (j.is_boolean()) {
    out[at] = j.get<bool>() ? 1.0 : 0.0;
  }
}

std::map<std::string, double> figures_of(const json& s) {
  std::map<std::string, double> out;
  for (const char* k : {summary_key::kWindow, summary_key::kPairs})
    if (s.contains(json::json_pointer(k))) numbers(s[json::json_pointer(k)], k, out);
  for (const char* k : {summary_key::kKineticFinal, summary_key::kResidual, summary_key::kSteps})
    if (s.contains(json::json_pointer(k)) && s[json::json_pointer(k)].is_number())
      out[k] = s[json::json_pointer(k)].get<double>();
  return out;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int run_ensemble(const Scene& scene, const RunOptions& opt) {
  const int K = std::max(1, opt.ensemble);
  const fs::path dir(opt.out_dir);
  const std::array<NodeOrder, 3> orders = {NodeOrder::scene, NodeOrder::rcm, NodeOrder::morton};
  const int first = static_cast<int>(std::find(orders.begin(), orders.end(), opt.node_order) - orders.begin());
  // The other members first, then member 0 (the run as asked, with its own end line), so that
  // DIR/summary.json appears only when every member has run.
  std::error_code ec;
  fs::create_directories(dir, ec);
  fs::remove(dir / "summary.json", ec);
  std::vector<json> sums(static_cast<std::size_t>(K));
  json members = json::array();
  members.push_back({{"member", 0}, {"dir", "."}, {"node_order", node_order_name(opt.node_order)}, {"jitter_seed", nullptr}});
  int rc = 0;
  for (int k = 1; k < K; ++k) {
    RunOptions ok = opt;
    ok.ensemble = 1;
    ok.progress = false;
    ok.out_dir = (dir / "members" / std::to_string(k)).string();
    ok.node_order = orders[static_cast<std::size_t>((first + k) % 3)];
    ok.jitter = kEnsembleJitter;
    ok.jitter_seed = static_cast<std::uint64_t>(k);
    const int rk = run_scene(scene, ok);
    if (rc == 0 && rk != 0) rc = rk;
    sums[static_cast<std::size_t>(k)] = read_json(fs::path(ok.out_dir) / "summary.json");
    members.push_back({{"member", k},
                       {"dir", "members/" + std::to_string(k)},
                       {"node_order", node_order_name(ok.node_order)},
                       {"jitter_seed", k}});
  }
  RunOptions o0 = opt;
  o0.ensemble = 1;
  const int r0 = run_scene(scene, o0);
  if (r0 != 0) rc = r0;
  sums[0] = read_json(dir / "summary.json");
  // What they share: the class, each figure's median and range.
  std::map<std::string, int> classes;
  std::map<std::string, std::vector<double>> values;
  for (std::size_t m = 0; m < sums.size(); ++m) {
    const json& s = sums[m];
    const std::string v = s.value("stability_verdict", std::string("failed"));
    ++classes[v];
    members[m]["stability_verdict"] = v;
    members[m]["state_hash"] = s.value("state_hash", std::string());
    members[m]["status"] = s.value("status", std::string());
    for (const auto& [k, x] : figures_of(s)) values[k].push_back(x);
  }
  json figures = json::object();
  for (const auto& [k, v] : values) {
    std::vector<double> finite;
    for (double x : v)
      if (std::isfinite(x)) finite.push_back(x);
    if (finite.empty()) continue;
    figures[k] = {{"median", median(finite)},
                  {"min", *std::min_element(finite.begin(), finite.end())},
                  {"max", *std::max_element(finite.begin(), finite.end())},
                  {"members", finite.size()}};
  }
  json sum = sums[0];
  const std::string shared = classes.size() == 1 ? classes.begin()->first : "flips";
  sum["ensemble"] = {{"members", K},
                     {"jitter_share_of_edge", kEnsembleJitter},
                     {"stability_verdict", shared},
                     {"classes", classes},
                     {"member_runs", members},
                     {"figures", figures}};
  sum["ensemble"]["member_0_stability_verdict"] = sums[0].value("stability_verdict", std::string());
  sum[json::json_pointer(summary_key::kStabilityVerdict)] = shared;
  write_summary(dir.string(), sum);
  if (opt.progress) {
    std::string counts;
    for (const auto& [c, n] : classes) counts += (counts.empty() ? "" : ", ") + std::to_string(n) + " " + c;
    std::fprintf(stderr, "harness: ensemble of %d: %s (%s)\n", K, shared.c_str(), counts.c_str());
  }
  return rc;
}

}  // namespace harness
