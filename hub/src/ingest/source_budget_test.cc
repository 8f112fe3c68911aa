// The per-source budget of tag checks: a flooding source is held to its rate, a node's source
// (authentic once) never is, other sources keep their own budget, the table is bounded.
#include "ingest/source_budget.h"

#include <arpa/inet.h>

#include <stdexcept>

#include <gtest/gtest.h>

namespace mocap {
namespace {

sockaddr_in Source(const char* ip, uint16_t port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  inet_pton(AF_INET, ip, &a.sin_addr);
  a.sin_port = htons(port);
  return a;
}

constexpr uint64_t kT0 = 1'000'000'000'000;

TEST(SourceBudget, AFloodingSourceGetsItsRateAndOthersTheirOwn) {
  SourceBudgetOptions o;
  o.checks_per_s = 100;
  SourceBudget budget(o);
  const sockaddr_in attacker = Source("10.0.0.9", 4000), other = Source("10.0.0.10", 4000);
  int allowed = 0;
  for (int i = 0; i < 10'000; ++i) allowed += budget.Allow(attacker, kT0 + uint64_t(i) * 100'000);  // 1 s
  EXPECT_GE(allowed, 100);  // the burst, then the rate: 100 + 100 per second
  EXPECT_LE(allowed, 201);
  EXPECT_TRUE(budget.Allow(other, kT0 + 999'900'000));  // a bucket of its own
  EXPECT_FALSE(budget.Allow(attacker, kT0 + 999'900'000));
}

TEST(SourceBudget, ANodesSourceIsNeverLimitedWhileItsTrustLasts) {
  SourceBudgetOptions o;
  o.checks_per_s = 10;
  o.trusted_for_ns = 2'000'000'000;
  SourceBudget budget(o);
  const sockaddr_in node = Source("10.0.0.2", 30000);
  budget.Trust(node, kT0);
  for (int i = 0; i < 1000; ++i) ASSERT_TRUE(budget.Allow(node, kT0 + uint64_t(i) * 1'000'000)) << i;
  // Trust ends: the node's source is limited like any other until it is authentic again.
  int allowed = 0;
  for (int i = 0; i < 100; ++i) allowed += budget.Allow(node, kT0 + 3'000'000'000 + uint64_t(i));
  EXPECT_LE(allowed, 10);
  budget.Trust(node, kT0 + 3'000'000'100);
  EXPECT_TRUE(budget.Allow(node, kT0 + 3'000'000'200));
}

TEST(SourceBudget, SourcesBeyondTheTableShareOneBucketAndIdleOnesLeave) {
  SourceBudgetOptions o;
  o.checks_per_s = 5;
  o.max_sources = 4;
  o.trusted_for_ns = 1'000'000'000;
  SourceBudget budget(o);
  for (uint16_t p = 1; p <= 4; ++p) EXPECT_TRUE(budget.Allow(Source("10.0.0.9", p), kT0));
  EXPECT_EQ(budget.sources(), 4u);
  int shared = 0;
  for (uint16_t p = 100; p < 200; ++p) shared += budget.Allow(Source("10.0.0.9", p), kT0);
  EXPECT_EQ(shared, 5);  // one bucket for all of them
  EXPECT_EQ(budget.sources(), 4u);
  // Two seconds later the four are idle: a new source gets a bucket of its own again.
  EXPECT_TRUE(budget.Allow(Source("10.0.0.11", 1), kT0 + 2'000'000'000));
  EXPECT_EQ(budget.sources(), 1u);
}

TEST(SourceBudget, OptionsAreChecked) {
  SourceBudgetOptions o;
  o.checks_per_s = 0.5;
  EXPECT_THROW(SourceBudget{o}, std::invalid_argument);
  o.checks_per_s = 100;
  o.max_sources = 0;
  EXPECT_THROW(SourceBudget{o}, std::invalid_argument);
}

}  // namespace
}  // namespace mocap
