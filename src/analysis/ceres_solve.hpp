// The solver settings every Ceres fit of nearcap_tuning shares (policy_fit.cpp,
// l_near_fit.cpp): dense QR, one thread so that a fit is reproducible bit for
// bit, no logging; a fit whose solution is unusable is an error naming it.
#pragma once

#include <ceres/ceres.h>

#include <string>

#include "nearcap/error.hpp"

namespace nearcap::analysis {

inline ceres::Solver::Options deterministic_solver_options(int max_iterations) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = max_iterations;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  return options;
}

// Solves; throws Error(Degenerate) "the WHAT fit failed: ..." when the
// solution is not usable.
inline ceres::Solver::Summary solve_or_throw(ceres::Problem& problem, const ceres::Solver::Options& options,
                                             const std::string& what) {
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (!summary.IsSolutionUsable())
    throw Error(ErrorKind::Degenerate, "the " + what + " fit failed: " + summary.message);
  return summary;
}

}  // namespace nearcap::analysis
