// nearcap/check.hpp — internal invariant checks that print their operands.
//
// NEARCAP_CHECK(cond) aborts with file:line and the condition when it fails;
// NEARCAP_CHECK_EQ(a, b) also prints both operands.  They stay on in release
// builds: they guard invariants whose violation would otherwise be a silent
// wrong answer.  Input faults are never checks; they are nearcap::Error.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

namespace nearcap::detail {
[[noreturn]] inline void check_failed(const char* file, int line, const std::string& what) {
  std::fprintf(stderr, "nearcap: internal check failed at %s:%d: %s\n", file, line, what.c_str());
  std::abort();
}
template <class A, class B>
std::string describe_pair(const char* ea, const char* eb, const A& a, const B& b) {
  std::ostringstream s;
  s << ea << " == " << eb << " (" << ea << " = " << a << ", " << eb << " = " << b << ")";
  return s.str();
}
}  // namespace nearcap::detail

#define NEARCAP_CHECK(cond) ((cond) ? (void)0 : ::nearcap::detail::check_failed(__FILE__, __LINE__, #cond))
#define NEARCAP_CHECK_EQ(a, b) \
  (((a) == (b))                \
       ? (void)0               \
       : ::nearcap::detail::check_failed(__FILE__, __LINE__, ::nearcap::detail::describe_pair(#a, #b, (a), (b))))
