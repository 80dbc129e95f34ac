// host/common/name_table.h: every enum's name table names each value once, with names that
// differ, and its parser and name function are each other's inverse; an unknown word is refused
// with a message that lists the names.
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "bvh/bvh.h"
#include "bvh/gpu_layout.h"
#include "common/error.h"
#include "common/name_table.h"
#include "hrpp/adaptive_predictor.h"
#include "hrpp/predictor_config.h"
#include "trace/ray_class.h"
#include "hrpp/ray_hash.h"
#include "kernel_names.h"
#include "trace/query_kind.h"
#include "trace/ray_order.h"

namespace hrpp {
namespace {

template <class E, std::size_t N>
void expect_well_formed(const NameTable<E, N>& table, const char* what) {
  std::set<std::string> names;
  std::set<E> values;
  for (const auto& [value, name] : table) {
    EXPECT_TRUE(names.insert(name).second) << what << ": name '" << name << "' twice";
    EXPECT_TRUE(values.insert(value).second) << what << ": a value named twice ('" << name << "')";
    EXPECT_STREQ(name_in(table, value), name) << what;
    EXPECT_EQ(parse_in(table, name, what), value) << what;
    EXPECT_EQ(value_map(table).at(name), value) << what;
  }
  EXPECT_EQ(names.size(), N) << what;
}

TEST(NameTable, EveryTableNamesEachValueOnce) {
  expect_well_formed(kQueryKindNames, "query kind");
  expect_well_formed(kRayClassNames, "ray class");
  expect_well_formed(kHashKindNames, "hash");
  expect_well_formed(kPredictorModeNames, "mode");
  expect_well_formed(kTablePolicyNames, "policy");
  expect_well_formed(kTablePresetNames, "preset");
  expect_well_formed(kNodeFormatNames, "node format");
  expect_well_formed(kNodeLayoutNames, "node layout");
  expect_well_formed(kRayOrderNames, "ray order");
  expect_well_formed(kBvhSplitsNames, "BVH splits");
  expect_well_formed(kProbeNames, "probe");
  expect_well_formed(kReasonNames, "reason");
  expect_well_formed(kKernelNames, "kernel");
}

// A table of the test's own, so that a new value of a real enum changes nothing here.
enum class Fruit { kApple, kPear };
constexpr NameTable<Fruit, 2> kFruitNames = {{{Fruit::kApple, "apple"}, {Fruit::kPear, "pear"}}};

TEST(NameTable, UnknownNamesAreRefusedWithTheList) {
  EXPECT_EQ(parse_in(kFruitNames, "pear", "--fruit: unknown fruit"), Fruit::kPear);
  try {
    parse_in(kFruitNames, "plum", "--fruit: unknown fruit");
    FAIL() << "plum parsed";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "--fruit: unknown fruit 'plum' (apple, pear)");
  }
  EXPECT_THROW(parse_in(kTablePolicyNames, "mru", "--table-policy"), Error);
  EXPECT_THROW(parse_hash_kind("md5"), Error);
  EXPECT_THROW(table_preset("huge"), Error);
  EXPECT_THROW(parse_ray_class("primary"), Error);
  EXPECT_STREQ(name_in(kFruitNames, static_cast<Fruit>(7)), "?");
}

}  // namespace
}  // namespace hrpp
