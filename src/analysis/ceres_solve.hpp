// The solver settings every Ceres fit of nearcap_tuning shares (policy_fit.cpp,
// l_near_fit.cpp): dense QR, one thread so that a fit is reproducible bit for
// bit, no logging; a fit whose solution is unusable is an error naming it.
//
// Ceres reports through glog (warnings such as "Residual block evaluation
// failed", written to stderr before glog is initialized).  A command's stderr
// is its one error line, so solves run with glog's output off; with the
// environment variable NEARCAP_SOLVER_LOG=1 glog keeps its output and each
// solve's full report goes to stderr.
#pragma once

#include <ceres/ceres.h>
#include <glog/logging.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "nearcap/error.hpp"

namespace nearcap::analysis {

inline bool solver_log_requested() {
  const char* env = std::getenv("NEARCAP_SOLVER_LOG");
  return env != nullptr && std::strcmp(env, "1") == 0;
}

inline ceres::Solver::Options deterministic_solver_options(int max_iterations) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = max_iterations;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  return options;
}

// Solves; throws Error(Degenerate) "the WHAT fit failed: ..." when the
// solution is not usable.
inline ceres::Solver::Summary solve_or_throw(ceres::Problem& problem, const ceres::Solver::Options& options,
                                             const std::string& what) {
  const bool log = solver_log_requested();
  // glog's messages below FATAL are dropped while the solver runs (the
  // previous level is restored after).
  const int previous_level = FLAGS_minloglevel;
  if (!log) FLAGS_minloglevel = google::GLOG_FATAL;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  FLAGS_minloglevel = previous_level;
  if (log) std::fprintf(stderr, "%s fit:\n%s\n", what.c_str(), summary.FullReport().c_str());
  if (!summary.IsSolutionUsable())
    throw Error(ErrorKind::Degenerate, "the " + what + " fit failed: " + summary.message);
  return summary;
}

}  // namespace nearcap::analysis
