// ids: agents, collectors and goals named by ids of their own kind, and
// tables indexed by one kind only.
#include "gather_core/ids.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <type_traits>
#include <utility>
#include <vector>

namespace gather {
namespace {

// Whether a Table can be indexed by an Index (the compiler's answer).
template <class Table, class Index, class = void>
struct indexable : std::false_type {};
template <class Table, class Index>
struct indexable<Table, Index, std::void_t<decltype(std::declval<Table&>()[std::declval<Index>()])>> : std::true_type {
};

// The point of the types: a collector is not an agent, an agent not a goal,
// and none of them a bare number, unless the code says so.
static_assert(!std::is_convertible_v<CollectorId, AgentId>, "a collector is not an agent");
static_assert(!std::is_convertible_v<AgentId, CollectorId>, "an agent is not a collector");
static_assert(!std::is_convertible_v<GoalId, AgentId>, "a goal is not an agent");
static_assert(!std::is_convertible_v<int, AgentId>, "a number is not an agent without AgentId(n)");
static_assert(!std::is_convertible_v<AgentId, int>, "an agent is not a number without value()");
static_assert(indexable<PerAgent<double>, AgentId>::value, "a per-agent table takes agent ids");
static_assert(!indexable<PerAgent<double>, CollectorId>::value, "a per-agent table refuses collector ids");
static_assert(!indexable<PerCollector<double>, AgentId>::value, "a per-collector table refuses agent ids");
static_assert(!indexable<PerAgent<double>, std::size_t>::value, "a per-agent table refuses plain indices");
static_assert(std::is_trivially_copyable_v<AgentId>, "ids copy like the integers they hold");

TEST(IdsTest, AnIdIsItsIndexAndNoneIsMinusOne) {
  const AgentId a(3);
  EXPECT_EQ(a.value(), 3);
  EXPECT_EQ(a.index(), 3u);
  EXPECT_EQ(AgentId::at_index(3), a);
  EXPECT_TRUE(a.valid());
  EXPECT_FALSE(AgentId().valid());
  EXPECT_EQ(AgentId().value(), -1);
  EXPECT_TRUE(a.within(4));
  EXPECT_FALSE(a.within(3));
  EXPECT_FALSE(AgentId(-1).within(4));
  EXPECT_FALSE(CollectorId(-7).valid());  // what a file may say; check_plan refuses it
  EXPECT_LT(AgentId(2), a);
  EXPECT_NE(AgentId(2), a);
}

TEST(IdsTest, IdsPrintTheirKind) {
  std::ostringstream text;
  text << AgentId(4) << ", " << CollectorId(1) << ", " << GoalId(17);
  EXPECT_EQ(text.str(), "agent 4, collector 1, goal 17");
  EXPECT_EQ(to_string(CollectorId()), "collector -1");
}

TEST(IdsTest, ATableIsIndexedByItsIdAndGrowsLikeAVector) {
  PerCollector<int> load(2, 0);
  EXPECT_EQ(load.count(), 2);
  load[CollectorId(1)] = 5;
  load.push_back(7);
  EXPECT_EQ(load.values(), (std::vector<int>{0, 5, 7}));
  EXPECT_EQ(load[CollectorId(2)], 7);
  EXPECT_EQ(load.back(), 7);
  const PerCollector<int> listed(std::vector<int>{0, 5, 7});
  EXPECT_EQ(listed, load);
  EXPECT_EQ(PerAgent<int>(3, 0).count(), 3);  // n entries of a value, never the list {3, 0}
  load.assign(-3, 1);
  EXPECT_TRUE(load.empty());
}

TEST(IdsTest, IdsRunFromZeroToNMinusOne) {
  std::vector<int> values;
  for (AgentId a : ids<AgentId>(3)) values.push_back(a.value());
  EXPECT_EQ(values, (std::vector<int>{0, 1, 2}));
  int none = 0;
  for (GoalId g : ids<GoalId>(-2)) none += 1 + g.value();
  EXPECT_EQ(none, 0);
}

}  // namespace
}  // namespace gather
