// Two planted defects that the sanitizer job must catch: `scripts/sanitize.sh --proof` runs
// only these (ctest label 'proof') and must fail. The default run leaves them out. Without
// sanitizers both tests pass, which is what makes them a proof of the job, not of fvx.
#include <gtest/gtest.h>

#include <climits>
#include <numeric>
#include <vector>

namespace {

/// Sums the first `count` values, reading one too many: the broken input is count == size.
int sum_reading_one_too_many(const std::vector<int>& values, int count) {
  int sum = 0;
  for (int i = 0; i <= count; ++i) sum += values.data()[i];
  return sum;
}

TEST(SanitizerProof, AddressSanitizerReportsAReadPastTheEnd) {
  const std::vector<int> values(4, 1);
  volatile int count = 4;
  EXPECT_NE(sum_reading_one_too_many(values, count), -1);
}

TEST(SanitizerProof, UndefinedBehaviorSanitizerReportsASignedOverflow) {
  volatile int largest = INT_MAX;
  const int next = largest + 1;
  EXPECT_NE(next, 0);
}

}  // namespace
