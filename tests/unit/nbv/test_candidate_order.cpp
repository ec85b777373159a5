// The lazily sorted candidate order against its oracle, a full sort by the same total order.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "../../../src/nbv/search.hpp"

namespace fvx::nbv::detail {
namespace {

TEST(CandidateOrder, ReadsInTheOrderOfAFullSort) {
  std::mt19937_64 rng(7);
  for (const std::size_t n : {0u, 1u, 5u, 1023u, 1024u, 1025u, 50000u}) {
    core::LargeVector<double> value(2 * n + 10, 0.0);
    // Few distinct values: many ties, broken by index.
    for (double& v : value) v = double(std::uniform_int_distribution<int>(0, 40)(rng));
    std::vector<std::size_t> cells;
    for (std::size_t i = 0; i < value.size(); ++i)
      if (i % 3 != 1) cells.push_back(i);
    cells.resize(n);
    std::shuffle(cells.begin(), cells.end(), rng);
    std::vector<std::size_t> oracle = cells;
    std::sort(oracle.begin(), oracle.end(), [&](std::size_t l, std::size_t r) {
      return value[l] > value[r] || (value[l] == value[r] && l < r);
    });
    CandidateOrder order(cells, value);
    ASSERT_EQ(order.size(), oracle.size());
    // Read the first few, then jump ahead, then everything: each read past the sorted part sorts.
    if (n > 3) {
      EXPECT_EQ(order[0], oracle[0]);
      EXPECT_EQ(order[n / 2], oracle[n / 2]);
    }
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(order[i], oracle[i]) << "n " << n << " at " << i;
  }
}

}  // namespace
}  // namespace fvx::nbv::detail
