// Fitting the switch policy's crack model with Ceres (see policy_fit.hpp).
#include "nearcap/analysis/policy_fit.hpp"

#include <ceres/ceres.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "ceres_solve.hpp"
#include "nearcap/error.hpp"

namespace nearcap::analysis {
namespace {

// One line of a CSV written by nearcap sweep: commas, fields quoted when they
// hold a comma or a quote, quotes doubled.
std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (std::size_t k = 0; k < line.size(); ++k) {
    const char c = line[k];
    if (quoted) {
      if (c == '"' && k + 1 < line.size() && line[k + 1] == '"') {
        out.back() += '"';
        ++k;
      } else if (c == '"') {
        quoted = false;
      } else {
        out.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      out.emplace_back();
    } else if (c != '\r') {
      out.back() += c;
    }
  }
  return out;
}

double to_number(const std::string& s, const std::string& where) {
  if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
  if (s == "inf") return std::numeric_limits<double>::infinity();
  if (s == "-inf") return -std::numeric_limits<double>::infinity();
  try {
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    if (used == s.size()) return v;
  } catch (const std::exception&) {
  }
  throw Error(ErrorKind::Parse, where + ": '" + s + "' is not a number");
}

// One row of a sweep CSV: its fields, the header's column indices, and where
// it is (file and line) for errors.
struct Row {
  std::vector<std::string> fields;
  const std::map<std::string, std::size_t>& column;
  std::string where;
};
// Calls visit for every row of the files, after checking each header holds
// the needed columns.
template <class Visit>
void for_each_row(const std::vector<std::string>& files, std::initializer_list<const char*> needed, Visit&& visit) {
  for (const std::string& file : files) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw Error(ErrorKind::Io, file + ": cannot read");
    std::string line;
    if (!std::getline(in, line)) throw Error(ErrorKind::Parse, file + ": empty, not a nearcap sweep CSV");
    const std::vector<std::string> header = csv_fields(line);
    std::map<std::string, std::size_t> column;
    for (std::size_t k = 0; k < header.size(); ++k) column[header[k]] = k;
    for (const char* c : needed)
      if (!column.count(c))
        throw Error(ErrorKind::Parse, file + ": line 1: missing column '" + c +
                                          "' (not a nearcap sweep CSV, or one from an older nearcap)");
    std::size_t number = 1;
    while (std::getline(in, line)) {
      ++number;
      if (line.empty()) continue;
      Row row{csv_fields(line), column, file + ": line " + std::to_string(number)};
      if (row.fields.size() != header.size()) throw Error(ErrorKind::Parse, row.where + ": wrong number of fields");
      visit(row);
    }
  }
}

// The logistic sample's cost: 2 logloss as a squared residual.
struct LogLoss {
  LogLoss(const std::vector<double>& x, int y) : x_(x), sign_(y ? 1.0 : -1.0) {}
  template <class T>
  bool operator()(T const* const* parameters, T* residual) const {
    const T* w = parameters[0];
    T z = parameters[1][0];
    for (std::size_t k = 0; k < x_.size(); ++k) z += w[k] * x_[k];
    const T m = -sign_ * z;  // logloss = softplus(m), computed stably
    using std::exp;
    using std::log;
    using std::sqrt;
    // Two branches that agree in value and slope at 0 (a max(m, 0) + abs(m)
    // form gives the wrong slope there, where every fit starts).
    const T softplus = m >= T(0) ? m + log(T(1) + exp(-m)) : log(T(1) + exp(m));
    // A floor under the square root: a sample classified beyond doubt has a
    // softplus that underflows to 0, where the root's slope is infinite.
    residual[0] = sqrt(T(2) * softplus + T(1e-200));
    return true;
  }
  std::vector<double> x_;
  double sign_;
};

struct Ridge {
  Ridge(std::size_t n, double l2) : n_(n), l2_(l2) {}
  template <class T>
  bool operator()(T const* const* parameters, T* residual) const {
    for (std::size_t k = 0; k < n_; ++k) residual[k] = T(l2_) * parameters[0][k];
    return true;
  }
  std::size_t n_;
  double l2_;
};

std::uint32_t fnv1a(const std::string& s) {
  std::uint32_t h = 2166136261u;
  for (unsigned char c : s) {
    h ^= c;
    h *= 16777619u;
  }
  return h;
}

}  // namespace

bool held_out_configuration(const std::string& configuration_id) { return fnv1a(configuration_id) % 5 == 0; }

std::vector<PolicySample> policy_samples(const std::vector<std::string>& files, gl::ShadowMethod capped,
                                         gl::ShadowMethod fallback, const std::string& variant) {
  struct Pair {
    std::optional<std::size_t> capped_cracks, fallback_cracks;
    ConditioningFeatures features;
    bool capped_fell_back = false;
  };
  std::map<std::pair<std::string, std::size_t>, Pair> pairs;
  const std::string capped_name(gl::to_string(capped)), fallback_name(gl::to_string(fallback));
  for_each_row(
      files,
      {"configuration", "light", "method", "variant", "cracks", "fallback", "refused", "light_frustum_defined",
       "light_near_distance", "l_far_over_width", "delta_over_width", "skew", "cond_light_transform",
       "cap_window_error_px", "coordinate_over_size", "l_near_over_l_far"},
      [&](const Row& row) {
        const auto& f = row.fields;
        auto col = [&](const char* name) { return row.column.at(name); };
        const std::string& where = row.where;
        const std::string& method = f[col("method")];
        if ((method != capped_name && method != fallback_name) || f[col("variant")] != variant ||
            f[col("refused")] == "1")
          return;
        Pair& p = pairs[{f[col("configuration")], static_cast<std::size_t>(to_number(f[col("light")], where))}];
        const auto cracks = static_cast<std::size_t>(to_number(f[col("cracks")], where));
        if (method == capped_name) {
          p.capped_cracks = cracks;
          p.capped_fell_back = !f[col("fallback")].empty();
          ConditioningFeatures& c = p.features;
          c.light_frustum_defined = f[col("light_frustum_defined")] == "1";
          c.light_near_distance = to_number(f[col("light_near_distance")], where);
          c.l_far_over_width = to_number(f[col("l_far_over_width")], where);
          c.delta_over_width = to_number(f[col("delta_over_width")], where);
          c.skew = to_number(f[col("skew")], where);
          c.cond_light_transform = to_number(f[col("cond_light_transform")], where);
          c.cap_window_error_px = to_number(f[col("cap_window_error_px")], where);
          c.coordinate_over_size = to_number(f[col("coordinate_over_size")], where);
          c.l_near_over_l_far = to_number(f[col("l_near_over_l_far")], where);
        } else {
          p.fallback_cracks = cracks;
        }
      });
  std::vector<PolicySample> out;
  for (const auto& [key, p] : pairs) {
    if (!p.capped_cracks || !p.fallback_cracks || p.capped_fell_back) continue;
    PolicySample s;
    s.configuration = key.first;
    s.light = key.second;
    bool finite = true;
    for (std::string_view name : kPolicyFeatures) {
      s.x.push_back(policy_feature(name, p.features));
      finite = finite && std::isfinite(s.x.back());
    }
    if (!finite) continue;
    s.crack = *p.capped_cracks > *p.fallback_cracks;
    s.held_out = held_out_configuration(s.configuration);
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<CostSample> cost_samples(const std::vector<std::string>& files, gl::ShadowMethod method,
                                     const std::string& variant) {
  std::vector<CostSample> out;
  const std::string name(gl::to_string(method));
  for_each_row(files,
               {"configuration", "method", "variant", "refused", "depth_triangles", "near_cap_triangles",
                "volume_triangles", "depth_fragments", "near_cap_fragments", "volume_fragments", "frame_ms"},
               [&](const Row& row) {
                 auto at = [&](const char* c) -> const std::string& { return row.fields[row.column.at(c)]; };
                 if (at("method") != name || at("variant") != variant || at("refused") == "1") return;
                 CostSample s;
                 s.configuration = at("configuration");
                 for (const char* c : {"depth_triangles", "near_cap_triangles", "volume_triangles"})
                   s.triangles += to_number(at(c), row.where);
                 for (const char* c : {"depth_fragments", "near_cap_fragments", "volume_fragments"})
                   s.fragments += to_number(at(c), row.where);
                 s.ms = to_number(at("frame_ms"), row.where);
                 s.held_out = held_out_configuration(s.configuration);
                 out.push_back(s);
               });
  return out;
}

namespace {
struct CostResidual {
  CostResidual(double mtriangles, double mfragments, double ms) : t_(mtriangles), f_(mfragments), ms_(ms) {}
  template <class T>
  bool operator()(const T* c, T* residual) const {
    residual[0] = c[0] + c[1] * t_ + c[2] * f_ - T(ms_);
    return true;
  }
  double t_, f_, ms_;
};
}  // namespace

CostModel fit_cost_model(const std::vector<CostSample>& samples, bool robust) {
  std::array<double, 3> c{0, 0, 0};
  ceres::Problem problem;
  std::size_t used = 0;
  for (const CostSample& s : samples) {
    if (s.held_out) continue;
    ++used;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<CostResidual, 1, 3>(
                                 new CostResidual(s.triangles * 1e-6, s.fragments * 1e-6, s.ms)),
                             robust ? new ceres::CauchyLoss(1.0) : nullptr, c.data());
  }
  if (used < 3) throw Error(ErrorKind::Usage, "a cost model needs at least 3 training rows of the method");
  solve_or_throw(problem, deterministic_solver_options(100), "cost");
  return {c[0], c[1], c[2]};
}

double median_relative_error(const CostModel& model, const std::vector<CostSample>& samples, bool held_out) {
  std::vector<double> e;
  for (const CostSample& s : samples)
    if (s.held_out == held_out && s.ms > 0)
      e.push_back(std::fabs(model.predict_ms(s.triangles, s.fragments) - s.ms) / s.ms);
  if (e.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::nth_element(e.begin(), e.begin() + static_cast<std::ptrdiff_t>(e.size() / 2), e.end());
  return e[e.size() / 2];
}

LogisticFit fit_logistic(const std::vector<std::vector<double>>& x, const std::vector<int>& y,
                         const LogisticFitOptions& options) {
  if (x.empty() || x.size() != y.size()) throw Error(ErrorKind::Usage, "fit_logistic: no samples, or labels missing");
  const std::size_t n = x.front().size();
  LogisticFit fit;
  fit.mean.assign(n, 0.0);
  fit.scale.assign(n, 0.0);
  for (const auto& row : x)
    for (std::size_t k = 0; k < n; ++k) fit.mean[k] += row[k] / static_cast<double>(x.size());
  for (const auto& row : x)
    for (std::size_t k = 0; k < n; ++k)
      fit.scale[k] += (row[k] - fit.mean[k]) * (row[k] - fit.mean[k]) / static_cast<double>(x.size());
  for (double& s : fit.scale) s = s > 0 ? std::sqrt(s) : 1.0;

  fit.weights.assign(n, 0.0);
  ceres::Problem problem;
  for (std::size_t i = 0; i < x.size(); ++i) {
    std::vector<double> standard(n);
    for (std::size_t k = 0; k < n; ++k) standard[k] = (x[i][k] - fit.mean[k]) / fit.scale[k];
    auto* cost = new ceres::DynamicAutoDiffCostFunction<LogLoss, 8>(new LogLoss(standard, y[i]));
    cost->AddParameterBlock(static_cast<int>(n));
    cost->AddParameterBlock(1);
    cost->SetNumResiduals(1);
    problem.AddResidualBlock(cost, options.robust ? new ceres::HuberLoss(options.huber_delta) : nullptr,
                             fit.weights.data(), &fit.bias);
  }
  if (options.l2 > 0) {
    auto* ridge = new ceres::DynamicAutoDiffCostFunction<Ridge, 8>(new Ridge(n, options.l2));
    ridge->AddParameterBlock(static_cast<int>(n));
    ridge->SetNumResiduals(static_cast<int>(n));
    problem.AddResidualBlock(ridge, nullptr, fit.weights.data());
  }
  ceres::Solver::Options solver = deterministic_solver_options(200);
  // Nearly separable data (a few cracks) send the weights far: bounded steps
  // in standardized units keep every trial point finite.
  solver.initial_trust_region_radius = 1.0;
  solver.max_trust_region_radius = 100.0;
  solver.max_num_consecutive_invalid_steps = 50;
  const ceres::Solver::Summary summary = solve_or_throw(problem, solver, "logistic");
  fit.iterations = static_cast<int>(summary.iterations.size());
  fit.final_cost = summary.final_cost;
  return fit;
}

Confusion confusion(const CrackModel& model, const std::vector<PolicySample>& samples, bool held_out) {
  Confusion c;
  for (const PolicySample& s : samples) {
    if (s.held_out != held_out) continue;
    double z = model.bias;
    for (std::size_t k = 0; k < model.weights.size(); ++k)
      z += model.weights[k] * (s.x[k] - model.mean[k]) / model.scale[k];
    const bool predicted = 1.0 / (1.0 + std::exp(-z)) >= model.threshold;
    ++c.samples;
    c.positives += s.crack;
    c.true_positives += s.crack && predicted;
    c.false_positives += !s.crack && predicted;
  }
  return c;
}

SwitchPolicy tune_policy(const std::vector<PolicySample>& all_samples, gl::ShadowMethod capped,
                         gl::ShadowMethod fallback, const std::string& command, const LogisticFitOptions& options,
                         const std::vector<std::string>& feature_names,
                         const std::vector<std::pair<gl::ShadowMethod, std::vector<CostSample>>>& costs) {
  // The chosen features' columns.
  std::vector<std::string> names = feature_names;
  if (names.empty()) names.assign(kPolicyFeatures.begin(), kPolicyFeatures.end());
  std::vector<std::size_t> columns;
  for (const std::string& name : names) {
    const auto it = std::find(kPolicyFeatures.begin(), kPolicyFeatures.end(), name);
    if (it == kPolicyFeatures.end()) throw Error(ErrorKind::Usage, "'" + name + "' is not a policy feature");
    columns.push_back(static_cast<std::size_t>(it - kPolicyFeatures.begin()));
  }
  std::vector<PolicySample> samples = all_samples;
  for (PolicySample& s : samples) {
    std::vector<double> x;
    for (std::size_t c : columns) x.push_back(s.x[c]);
    s.x = std::move(x);
  }
  std::vector<std::vector<double>> x;
  std::vector<int> y;
  for (const PolicySample& s : samples)
    if (!s.held_out) {
      x.push_back(s.x);
      y.push_back(s.crack ? 1 : 0);
    }
  if (x.empty())
    throw Error(ErrorKind::Usage,
                "no training samples: the rows need both methods in the policy's variant (sweep with "
                "--switch-clamp clamp-far, or say which with --variant)");
  SwitchPolicy p;
  p.capped_method = capped;
  p.fallback_method = fallback;
  CrackModel& m = p.crack_model;
  const bool any_crack = std::find(y.begin(), y.end(), 1) != y.end();
  nlohmann::json fit_json;
  if (any_crack) {
    const LogisticFit fit = fit_logistic(x, y, options);
    m.features = names;
    m.mean = fit.mean;
    m.scale = fit.scale;
    m.weights = fit.weights;
    m.bias = fit.bias;
    // Every training crack predicted: the smallest positive's probability, halved.
    double lowest = 1.0;
    for (std::size_t i = 0; i < x.size(); ++i)
      if (y[i]) {
        double z = m.bias;
        for (std::size_t k = 0; k < x[i].size(); ++k) z += m.weights[k] * (x[i][k] - m.mean[k]) / m.scale[k];
        lowest = std::min(lowest, 1.0 / (1.0 + std::exp(-z)));
      }
    m.threshold = std::clamp(lowest / 2, 1e-12, 0.5);
    fit_json = {{"iterations", fit.iterations},
                {"final_cost", fit.final_cost},
                {"robust", options.robust},
                {"huber_delta", options.huber_delta},
                {"l2", options.l2}};
  } else {
    // No training pair where the capped method cracks more than the
    // fallback: nothing to separate, no fit.  A model without features
    // whose probability, 1 / (1 + e^30), is below any threshold: it never
    // predicts a crack (the held-out side below says whether that holds).
    m.bias = -30;
    m.threshold = 1;
    fit_json = {{"none", "no training pair where the capped method cracks more than the fallback"}};
  }
  const Confusion train = confusion(m, samples, false), held = confusion(m, samples, true);
  auto side = [](const Confusion& c) {
    return nlohmann::json{{"samples", c.samples},
                          {"cracks", c.positives},
                          {"cracks_predicted", c.true_positives},
                          {"false_alarms", c.false_positives}};
  };
  nlohmann::json prov{{"command", command},
                      {"split", "held out: FNV-1a(configuration) % 5 == 0"},
                      {"fit", fit_json},
                      {"train", side(train)},
                      {"held_out", side(held)}};
  nlohmann::json cost = nlohmann::json::object();
  for (const auto& [method, rows] : costs) {
    const CostModel cm = fit_cost_model(rows, options.robust);
    p.cost_models.emplace_back(method, cm);
    std::size_t held_rows = 0;
    for (const CostSample& s : rows) held_rows += s.held_out;
    cost[std::string(gl::to_string(method))] = {
        {"rows", rows.size()},
        {"held_out_rows", held_rows},
        {"train_median_relative_error", median_relative_error(cm, rows, false)},
        {"held_out_median_relative_error", median_relative_error(cm, rows, true)}};
  }
  if (!costs.empty()) prov["cost"] = cost;
  // The command names the CSV files: a name that is not UTF-8 gets U+FFFD.
  p.provenance_json = prov.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return p;
}

}  // namespace nearcap::analysis
