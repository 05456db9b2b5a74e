// compare_values (engine/store/value_difference.hpp): floats equal within
// |a - b| <= atol + rtol |b|, NaN equal to NaN, integers and strings exact; the
// largest absolute and relative differences and where they are.

#include "engine/store/value_difference.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace ggk::engine {
namespace {

using ElementClass = Hdf5File::ElementClass;

template <class T>
void append(Hdf5File::Values& values, const std::vector<T>& elements, ElementClass element_class,
            const std::string& member = "") {
  const std::size_t offset = values.bytes.size();
  values.bytes.resize(offset + elements.size() * sizeof(T));
  std::memcpy(values.bytes.data() + offset, elements.data(), elements.size() * sizeof(T));
  values.parts.push_back({member, element_class, sizeof(T)});
}

Hdf5File::Values doubles(const std::vector<double>& elements,
                         std::vector<std::int64_t> shape = {}) {
  Hdf5File::Values values;
  values.type = "float64";
  values.shape = shape.empty() ? std::vector<std::int64_t>{std::int64_t(elements.size())} : shape;
  append(values, elements, ElementClass::kFloat);
  return values;
}

TEST(ValueDifference, IdenticalValuesHaveNoDifference) {
  const ValuesDifference d = compare_values(doubles({1, 2, 3}), doubles({1, 2, 3}), {});
  EXPECT_TRUE(d.equal());
  EXPECT_EQ(d.elements, 3);
  EXPECT_EQ(d.bitwise, 0);
  EXPECT_FALSE(d.absolute_at.has_value());
}

TEST(ValueDifference, FloatsAreEqualWithinRtolAndAtol) {
  const Hdf5File::Values a = doubles({1.0, 100.0, 0.0});
  const Hdf5File::Values b = doubles({1.0 + 1e-9, 100.0 - 2e-7, 1e-12});
  // Bit for bit: all three differ.
  const ValuesDifference exact = compare_values(a, b, {});
  EXPECT_EQ(exact.differing, 3);
  // |1e-12 - 0| <= atol alone decides the zero; rtol 1e-8 covers the others
  // (2e-7 <= 1e-8 * 100 - 2e-7 ~ 1e-6).
  const ValuesDifference loose = compare_values(a, b, {1e-8, 1e-11});
  EXPECT_TRUE(loose.equal());
  EXPECT_EQ(loose.bitwise, 3);
  // rtol alone cannot cover a change away from zero (relative difference infinite).
  const ValuesDifference relative_only = compare_values(a, b, {1e-8, 0.0});
  EXPECT_EQ(relative_only.differing, 1);
  EXPECT_EQ(relative_only.first_differing->index, 2);
  // The largest absolute difference is the 2e-7 at index 1; the largest relative
  // is at index 2: 1e-12 away from b = 1e-12.
  EXPECT_NEAR(loose.largest_absolute, 2e-7, 1e-12);
  EXPECT_EQ(loose.absolute_at->index, 1);
  EXPECT_DOUBLE_EQ(loose.largest_relative, 1.0);
  EXPECT_EQ(loose.relative_at->index, 2);
}

TEST(ValueDifference, NanEqualsNanAndInfinityOnlyItself) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(compare_values(doubles({nan, inf}), doubles({nan, inf}), {1e-3, 1e-3}).equal());
  const ValuesDifference d = compare_values(doubles({nan, inf}), doubles({1.0, -inf}), {1, 1});
  EXPECT_EQ(d.differing, 2);
  EXPECT_FALSE(d.absolute_at.has_value());  // no finite difference to report
  EXPECT_EQ(d.first_differing->index, 0);
}

TEST(ValueDifference, IntegersAreExactWhateverTheTolerance) {
  Hdf5File::Values a, b;
  a.type = b.type = "int32";
  a.shape = b.shape = {2, 2};
  append(a, std::vector<std::int32_t>{1, 2, 3, 4}, ElementClass::kSigned);
  append(b, std::vector<std::int32_t>{1, 2, 3, -5}, ElementClass::kSigned);
  const ValuesDifference d = compare_values(a, b, {0.5, 100.0});
  EXPECT_EQ(d.differing, 1);
  EXPECT_DOUBLE_EQ(d.largest_absolute, 9.0);
  EXPECT_EQ(element_place(*d.absolute_at, a.shape), "[1, 1]");
  EXPECT_NE(
      describe_difference(d, a.shape).find("largest absolute difference 9 at [1, 1] (4 vs -5)"),
      std::string::npos)
      << describe_difference(d, a.shape);
}

TEST(ValueDifference, TableColumnsAreNamedAndStringsCompared) {
  // A compound of 3 rows: kernels (int32), basis (string), sigma (float64).
  Hdf5File::Values a, b;
  a.type = b.type = "{kernels:int32;basis:string;sigma:float64;}";
  a.shape = b.shape = {3};
  append(a, std::vector<std::int32_t>{4, 8, 16}, ElementClass::kSigned, "kernels");
  append(b, std::vector<std::int32_t>{4, 8, 16}, ElementClass::kSigned, "kernels");
  a.parts.push_back({"basis", ElementClass::kString, 0});
  b.parts.push_back({"basis", ElementClass::kString, 0});
  a.strings = {"ggk", "ggk", "ogk"};
  b.strings = {"ggk", "ogk", "ogk"};
  append(a, std::vector<double>{1.0, 2.0, 3.0}, ElementClass::kFloat, "sigma");
  append(b, std::vector<double>{1.0, 2.0, 3.5}, ElementClass::kFloat, "sigma");
  const ValuesDifference d = compare_values(a, b, {1e-6, 0.0});
  EXPECT_EQ(d.elements, 9);
  EXPECT_EQ(d.differing, 2);
  EXPECT_EQ(d.first_differing->member, "basis");
  EXPECT_EQ(element_place(*d.first_differing, a.shape), "row 1, column basis");
  EXPECT_EQ(element_place(*d.absolute_at, a.shape), "row 2, column sigma");
  const std::string text = describe_difference(d, a.shape);
  EXPECT_NE(text.find("first at row 1, column basis (\"ggk\" vs \"ogk\")"), std::string::npos)
      << text;
}

}  // namespace
}  // namespace ggk::engine
