// LS_PROP: a RapidCheck property registered as a GoogleTest test that runs a
// fixed number of cases: kDefaultCases normally, LOCKSTEP_LONG_CASES in the
// long build (tests/fixed/CMakeLists.txt, CTest label "long"). RC_PARAMS still
// works (seed=..., or a larger max_success).
#pragma once
#include <algorithm>
#include <cstdint>
#include <optional>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#ifndef LOCKSTEP_LONG_CASES
#define LOCKSTEP_LONG_CASES 0
#endif

namespace lockstep_test {

inline constexpr int kDefaultCases = 20000;
inline constexpr int kCases = LOCKSTEP_LONG_CASES > 0 ? LOCKSTEP_LONG_CASES : kDefaultCases;
inline constexpr bool kLongRun = LOCKSTEP_LONG_CASES > 0;

// `seed`: rapidcheck's seed for this property (the same cases every run);
// none: the configured one (RC_PARAMS, else random).
template <class Testable>
void check_prop(Testable&& testable, int cases, std::optional<std::uint64_t> seed = std::nullopt) {
  rc::detail::TestParams params = rc::detail::configuration().testParams;
  params.maxSuccess = std::max(params.maxSuccess, cases);
  if (seed) params.seed = *seed;
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  rc::detail::TestMetadata metadata;
  metadata.id = std::string(info->test_suite_name()) + "/" + info->name();
  metadata.description = info->name();
  const auto result = rc::detail::checkTestable(std::forward<Testable>(testable), metadata, params);
  if (!result.template is<rc::detail::SuccessResult>()) {
    std::ostringstream ss;
    rc::detail::printResultMessage(result, ss);
    FAIL() << ss.str();
  }
}

}  // namespace lockstep_test

#define LS_PROP(Suite, Name)                                                      \
  static void lsProp_##Suite##_##Name();                                          \
  TEST(Suite, Name) { ::lockstep_test::check_prop(&lsProp_##Suite##_##Name, ::lockstep_test::kCases); } \
  static void lsProp_##Suite##_##Name()
