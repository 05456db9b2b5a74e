#include "engine/hdf5/hdf5_file.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <bit>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

// A fresh directory per test, removed afterwards.
class Hdf5FileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    static std::atomic<int> counter{0};
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("ggk_hdf5_file_test_" + std::to_string(::getpid()) + "_" +
                                        std::to_string(counter++) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path file_path(const std::string& name = "store.h5") const { return dir_ / name; }

  fs::path dir_;
};

::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" does not contain \"" << part << "\"";
}

// The message of the std::runtime_error that `action` throws ("" if none).
template <class Action>
std::string error_message(Action&& action) {
  try {
    action();
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  ADD_FAILURE() << "expected a std::runtime_error";
  return "";
}

std::vector<std::uint64_t> bits_of(const std::vector<double>& values) {
  std::vector<std::uint64_t> bits;
  for (const double value : values) bits.push_back(std::bit_cast<std::uint64_t>(value));
  return bits;
}

TEST_F(Hdf5FileTest, DoubleVectorRoundTripsBitForBitIncludingNanAndInfinity) {
  std::vector<double> values = {0.0,
                                -0.0,
                                1.5,
                                -2.25e300,
                                std::numeric_limits<double>::denorm_min(),
                                std::numeric_limits<double>::quiet_NaN(),
                                -std::numeric_limits<double>::quiet_NaN(),
                                std::numeric_limits<double>::infinity(),
                                -std::numeric_limits<double>::infinity()};
  // Enough values for several chunks.
  std::mt19937_64 random(7);
  std::normal_distribution<double> normal;
  for (int i = 0; i < 100000; ++i) values.push_back(normal(random));
  {
    auto file = Hdf5File::create(file_path());
    file.write_vector("/maze/run_000/samples/rewards", values);
  }
  const auto file = Hdf5File::open_read_only(file_path());
  const std::vector<double> read = file.read_vector<double>("/maze/run_000/samples/rewards");
  EXPECT_EQ(bits_of(read), bits_of(values));
  EXPECT_EQ(file.dataset_shape("/maze/run_000/samples/rewards"),
            std::vector<std::int64_t>{static_cast<std::int64_t>(values.size())});
}

TEST_F(Hdf5FileTest, IntegerAndFloatVectorsRoundTrip) {
  const std::vector<float> floats = {1.0F, -3.5F, std::numeric_limits<float>::infinity(), 1e-30F};
  const std::vector<std::int32_t> int32s = {0, -1, std::numeric_limits<std::int32_t>::min(),
                                            std::numeric_limits<std::int32_t>::max()};
  const std::vector<std::int64_t> int64s = {0, -1, std::numeric_limits<std::int64_t>::min(),
                                            std::numeric_limits<std::int64_t>::max()};
  std::vector<std::uint8_t> uint8s;
  for (int i = 0; i < 256; ++i) uint8s.push_back(static_cast<std::uint8_t>(i));
  {
    auto file = Hdf5File::create(file_path());
    file.write_vector("f", floats);
    file.write_vector("i32", int32s);
    file.write_vector("i64", int64s);
    file.write_vector("u8", uint8s);
  }
  const auto file = Hdf5File::open_read_only(file_path());
  EXPECT_EQ(file.read_vector<float>("/f"), floats);
  EXPECT_EQ(file.read_vector<std::int32_t>("/i32"), int32s);
  EXPECT_EQ(file.read_vector<std::int64_t>("/i64"), int64s);
  EXPECT_EQ(file.read_vector<std::uint8_t>("/u8"), uint8s);
}

TEST_F(Hdf5FileTest, EmptyDatasetsOfEveryKindRoundTrip) {
  {
    auto file = Hdf5File::create(file_path());
    file.write_vector("d", std::vector<double>{});
    file.write_vector("f", std::vector<float>{});
    file.write_vector("i32", std::vector<std::int32_t>{});
    file.write_vector("i64", std::vector<std::int64_t>{});
    file.write_vector("u8", std::vector<std::uint8_t>{});
    file.write_matrix("m0x3", 0, 3, std::vector<double>{});
    file.write_matrix("m4x0", 4, 0, std::vector<std::int32_t>{});
    file.write_strings("s", std::vector<std::string>{});
    file.write_csr("csr", CsrMatrix(0, 0));
  }
  const auto file = Hdf5File::open_read_only(file_path());
  EXPECT_TRUE(file.read_vector<double>("d").empty());
  EXPECT_TRUE(file.read_vector<float>("f").empty());
  EXPECT_TRUE(file.read_vector<std::int32_t>("i32").empty());
  EXPECT_TRUE(file.read_vector<std::int64_t>("i64").empty());
  EXPECT_TRUE(file.read_vector<std::uint8_t>("u8").empty());
  EXPECT_EQ(file.dataset_shape("d"), std::vector<std::int64_t>{0});
  const auto m0x3 = file.read_matrix<double>("m0x3");
  EXPECT_EQ(m0x3.rows, 0);
  EXPECT_EQ(m0x3.cols, 3);
  EXPECT_TRUE(m0x3.data.empty());
  const auto m4x0 = file.read_matrix<std::int32_t>("m4x0");
  EXPECT_EQ(m4x0.rows, 4);
  EXPECT_EQ(m4x0.cols, 0);
  EXPECT_TRUE(file.read_strings("s").empty());
  const CsrArrays csr = file.read_csr("csr");
  EXPECT_EQ(csr.rows, 0);
  EXPECT_EQ(csr.cols, 0);
  EXPECT_EQ(csr.indptr, std::vector<std::int64_t>{0});
  EXPECT_TRUE(csr.indices.empty());
  EXPECT_TRUE(csr.data.empty());
}

TEST_F(Hdf5FileTest, MatricesRoundTripRowMajor) {
  const std::vector<double> doubles = {1, 2, 3, 4, 5, 6};  // 2 x 3
  std::vector<std::int32_t> ints(1000 * 7);
  for (std::size_t i = 0; i < ints.size(); ++i) ints[i] = static_cast<std::int32_t>(i) - 500;
  {
    auto file = Hdf5File::create(file_path());
    file.write_matrix("fits/A", 2, 3, doubles);
    file.write_matrix("fits/policy", 1000, 7, ints);
  }
  const auto file = Hdf5File::open_read_only(file_path());
  const auto a = file.read_matrix<double>("fits/A");
  EXPECT_EQ(a.rows, 2);
  EXPECT_EQ(a.cols, 3);
  EXPECT_EQ(a.data, doubles);
  EXPECT_EQ(file.dataset_shape("fits/A"), (std::vector<std::int64_t>{2, 3}));
  const auto policy = file.read_matrix<std::int32_t>("fits/policy");
  EXPECT_EQ(policy.rows, 1000);
  EXPECT_EQ(policy.cols, 7);
  EXPECT_EQ(policy.data, ints);
}

TEST_F(Hdf5FileTest, ShapeAndTypeMismatchesAreErrorsNamingThePath) {
  auto file = Hdf5File::create(file_path());
  EXPECT_TRUE(contains(error_message([&] { file.write_matrix("m", 2, 3, std::vector<double>(5)); }),
                       "'/m'"));
  EXPECT_FALSE(file.exists("m"));
  file.write_vector("ints", std::vector<std::int32_t>{1, 2});
  file.write_matrix("matrix", 1, 2, std::vector<double>{1, 2});
  EXPECT_TRUE(contains(error_message([&] { file.read_vector<std::int64_t>("ints"); }),
                       "'/ints': holds int32, not int64"));
  EXPECT_TRUE(contains(error_message([&] { file.read_vector<double>("matrix"); }),
                       "'/matrix': has rank 2"));
  EXPECT_TRUE(contains(error_message([&] { file.read_matrix<double>("ints"); }), "'/ints'"));
  EXPECT_TRUE(contains(error_message([&] { file.read_vector<double>("missing"); }), "'/missing'"));
}

TEST_F(Hdf5FileTest, Utf8StringsRoundTrip) {
  const std::vector<std::string> strings = {"",       "ggk",      "θ = 0.5 rad",
                                            "日本語", "🤖 arm", std::string(10000, 'x')};
  {
    auto file = Hdf5File::create(file_path());
    file.write_strings("names", strings);
  }
  const auto file = Hdf5File::open_read_only(file_path());
  EXPECT_EQ(file.read_strings("names"), strings);
}

TEST_F(Hdf5FileTest, StringWithNulIsRejected) {
  auto file = Hdf5File::create(file_path());
  const std::vector<std::string> strings = {std::string("a\0b", 3)};
  EXPECT_TRUE(contains(error_message([&] { file.write_strings("s", strings); }), "NUL"));
  EXPECT_FALSE(file.exists("s"));
}

TEST_F(Hdf5FileTest, AttributesRoundTripOnRootGroupsAndDatasets) {
  std::string job = "name = \"maze\"\n# θ, 日本語\nruns = 20\n";
  job += std::string(100000, '#');  // larger than HDF5's 64 KiB compact attribute limit
  const std::vector<std::int64_t> shape = {3, -4, 5};
  {
    auto file = Hdf5File::create(file_path());
    file.write_string_attribute("/", "job", job);
    file.write_int64_attribute("/", "seed", std::numeric_limits<std::int64_t>::min());
    file.create_group("/maze/run_000");
    file.write_double_attribute("/maze/run_000", "seconds", 12.5);
    file.write_double_attribute("/maze/run_000", "nan", std::nan(""));
    file.write_vector("/maze/run_000/data", std::vector<double>{1.0});
    file.write_string_attribute("/maze/run_000/data", "unit", "m/s²");
    file.write_int64_array_attribute("/maze/run_000/data", "dims", shape);
    file.write_string_attribute("/maze", "empty", "");
  }
  const auto file = Hdf5File::open_read_only(file_path());
  EXPECT_EQ(file.read_string_attribute("/", "job"), job);
  EXPECT_EQ(file.read_int64_attribute("/", "seed"), std::numeric_limits<std::int64_t>::min());
  EXPECT_EQ(file.read_double_attribute("/maze/run_000", "seconds"), 12.5);
  EXPECT_TRUE(std::isnan(file.read_double_attribute("/maze/run_000", "nan")));
  EXPECT_EQ(file.read_string_attribute("/maze/run_000/data", "unit"), "m/s²");
  EXPECT_EQ(file.read_int64_array_attribute("/maze/run_000/data", "dims"), shape);
  EXPECT_EQ(file.read_string_attribute("maze", "empty"), "");
  EXPECT_TRUE(file.has_attribute("/", "job"));
  EXPECT_FALSE(file.has_attribute("/", "jobs"));
  EXPECT_TRUE(
      contains(error_message([&] { file.read_int64_attribute("/maze/run_000", "seconds"); }),
               "holds float64"));
  EXPECT_TRUE(
      contains(error_message([&] { file.read_string_attribute("/", "seed"); }), "not a string"));
  EXPECT_TRUE(
      contains(error_message([&] { file.read_int64_attribute("/maze/run_000/data", "dims"); }),
               "3 elements"));
  EXPECT_TRUE(contains(error_message([&] { file.has_attribute("/nowhere", "x"); }),
                       "'/nowhere': no such object"));
}

TEST_F(Hdf5FileTest, ExistingAttributeIsAnErrorUntilRemoved) {
  auto file = Hdf5File::create(file_path());
  file.write_int64_attribute("/", "complete", 0);
  EXPECT_TRUE(contains(error_message([&] { file.write_int64_attribute("/", "complete", 1); }),
                       "attribute 'complete' already exists"));
  file.remove_attribute("/", "complete");
  EXPECT_FALSE(file.has_attribute("/", "complete"));
  file.write_int64_attribute("/", "complete", 1);
  EXPECT_EQ(file.read_int64_attribute("/", "complete"), 1);
}

CsrMatrix random_sparse_matrix(int rows, int cols, double density, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<Eigen::Triplet<double, std::int32_t>> triplets;
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      if (uniform(random) < density) triplets.emplace_back(i, j, uniform(random) - 0.5);
    }
  }
  CsrMatrix matrix(rows, cols);
  matrix.setFromTriplets(triplets.begin(), triplets.end());
  matrix.makeCompressed();
  return matrix;
}

TEST_F(Hdf5FileTest, CsrTripleMatchesEigenSparseMatrix) {
  const CsrMatrix matrix = random_sparse_matrix(50, 40, 0.1, 3);
  ASSERT_GT(matrix.nonZeros(), 100);
  CsrMatrix uncompressed(4, 5);
  uncompressed.reserve(Eigen::VectorXi::Constant(4, 3));  // per-row room: uncompressed mode
  uncompressed.insert(0, 1) = 1.5;
  uncompressed.insert(2, 4) = -2.0;
  uncompressed.insert(2, 0) = 3.0;
  ASSERT_FALSE(uncompressed.isCompressed());
  const CsrMatrix no_entries(5, 7);
  {
    auto file = Hdf5File::create(file_path());
    file.write_csr("/maze/run_000/features", matrix);
    file.write_csr("/maze/run_000/graph", uncompressed, "weights");
    file.write_csr("/maze/run_000/zero", no_entries);
  }
  const auto file = Hdf5File::open_read_only(file_path());
  const CsrArrays csr = file.read_csr("/maze/run_000/features");
  EXPECT_EQ(csr.rows, 50);
  EXPECT_EQ(csr.cols, 40);
  ASSERT_EQ(csr.indptr.size(), 51U);
  for (int i = 0; i <= 50; ++i) EXPECT_EQ(csr.indptr[i], matrix.outerIndexPtr()[i]);
  const auto nnz = static_cast<std::size_t>(matrix.nonZeros());
  EXPECT_EQ(csr.indices,
            std::vector<std::int32_t>(matrix.innerIndexPtr(), matrix.innerIndexPtr() + nnz));
  EXPECT_EQ(csr.data, std::vector<double>(matrix.valuePtr(), matrix.valuePtr() + nnz));
  // The group holds exactly the documented layout.
  EXPECT_EQ(file.read_int64_array_attribute("/maze/run_000/features", "shape"),
            (std::vector<std::int64_t>{50, 40}));
  EXPECT_EQ(file.read_vector<std::int64_t>("/maze/run_000/features/indptr"), csr.indptr);
  EXPECT_EQ(file.read_vector<std::int32_t>("/maze/run_000/features/indices"), csr.indices);
  EXPECT_EQ(file.read_vector<double>("/maze/run_000/features/data"), csr.data);

  const CsrMatrix read = file.read_csr_matrix("/maze/run_000/features");
  EXPECT_EQ(Eigen::MatrixXd(read), Eigen::MatrixXd(matrix));
  const CsrMatrix graph = file.read_csr_matrix("/maze/run_000/graph", "weights");
  EXPECT_EQ(Eigen::MatrixXd(graph), Eigen::MatrixXd(uncompressed));
  EXPECT_TRUE(file.exists("/maze/run_000/graph/weights"));
  EXPECT_FALSE(file.exists("/maze/run_000/graph/data"));
  const CsrMatrix zero = file.read_csr_matrix("/maze/run_000/zero");
  EXPECT_EQ(zero.rows(), 5);
  EXPECT_EQ(zero.cols(), 7);
  EXPECT_EQ(zero.nonZeros(), 0);
}

TEST_F(Hdf5FileTest, InvalidCsrIsRejectedBeforeAnythingIsWritten) {
  auto file = Hdf5File::create(file_path());
  const std::vector<std::int64_t> indptr = {0, 1, 2};
  const std::vector<std::int32_t> out_of_range = {0, 3};
  const std::vector<double> values = {1.0, 2.0};
  EXPECT_TRUE(
      contains(error_message([&] { file.write_csr("bad", 2, 3, indptr, out_of_range, values); }),
               "column index 3 outside [0, 3)"));
  EXPECT_FALSE(file.exists("bad"));
  const std::vector<std::int64_t> short_indptr = {0, 2};
  const std::vector<std::int32_t> indices = {0, 1};
  EXPECT_TRUE(
      contains(error_message([&] { file.write_csr("bad", 2, 3, short_indptr, indices, values); }),
               "indptr has 2 entries for 2 rows"));
  const std::vector<std::int64_t> decreasing = {0, 2, 1};
  EXPECT_TRUE(
      contains(error_message([&] { file.write_csr("bad", 2, 3, decreasing, indices, values); }),
               "decreases"));
  EXPECT_FALSE(file.exists("bad"));
}

std::vector<TableColumn> summary_columns() {
  return {{"basis", ColumnType::kString, 8},
          {"kernels", ColumnType::kInt32, 0},
          {"run", ColumnType::kInt64, 0},
          {"mean_return", ColumnType::kFloat64, 0},
          {"status", ColumnType::kString, 0}};  // variable length
}

TableRow summary_row(int i) {
  const std::string basis = i % 2 == 0 ? "ggk" : "ogk-θ";  // 7 bytes of UTF-8
  const std::string status = i % 3 == 0 ? "" : std::string(static_cast<std::size_t>(i), 'x') + "é";
  return {basis, std::int32_t{10 * i}, std::int64_t{i} << 40, 0.5 * i - 3.0, status};
}

TEST_F(Hdf5FileTest, TableAppendsInBatchesAndReadsBackRowByRow) {
  const auto columns = summary_columns();
  std::vector<TableRow> expected;
  {
    auto file = Hdf5File::create(file_path());
    file.create_table("/maze/summary", columns, 16);
    EXPECT_TRUE(file.read_table("/maze/summary").empty());
    for (const int batch_size : {1, 0, 5, 40}) {  // crosses chunk boundaries
      std::vector<TableRow> batch;
      for (int i = 0; i < batch_size; ++i)
        batch.push_back(summary_row(static_cast<int>(expected.size()) + i));
      file.append_rows("/maze/summary", batch);
      expected.insert(expected.end(), batch.begin(), batch.end());
    }
  }
  {
    // Appending works after reopening: the columns come from the file.
    auto file = Hdf5File::open_read_write(file_path());
    EXPECT_EQ(file.read_table_columns("/maze/summary"), columns);
    const std::vector<TableRow> more = {summary_row(46), summary_row(47)};
    file.append_rows("/maze/summary", more);
    expected.insert(expected.end(), more.begin(), more.end());
  }
  const auto file = Hdf5File::open_read_only(file_path());
  const std::vector<TableRow> rows = file.read_table("/maze/summary");
  ASSERT_EQ(rows.size(), expected.size());
  for (std::size_t r = 0; r < rows.size(); ++r) EXPECT_EQ(rows[r], expected[r]) << "row " << r;
  EXPECT_EQ(file.dataset_shape("/maze/summary"),
            std::vector<std::int64_t>{static_cast<std::int64_t>(expected.size())});
}

TEST_F(Hdf5FileTest, BadTableRowsAreRejectedAndAddNothing) {
  auto file = Hdf5File::create(file_path());
  file.create_table("t", summary_columns());
  const std::vector<TableRow> good = {summary_row(0)};
  file.append_rows("t", good);

  std::vector<TableRow> wrong_type = {summary_row(1), summary_row(2)};
  wrong_type[1][1] = std::int64_t{3};  // int64 in the int32 column
  EXPECT_TRUE(contains(error_message([&] { file.append_rows("t", wrong_type); }),
                       "row 1, column 'kernels': expected a value of type int32"));
  std::vector<TableRow> too_long = {summary_row(1)};
  too_long[0][0] = std::string("gaussian");  // 8 bytes fit exactly
  file.append_rows("t", too_long);
  too_long[0][0] = std::string("gaussians");
  EXPECT_TRUE(contains(error_message([&] { file.append_rows("t", too_long); }),
                       "string of 9 bytes exceeds the column's 8"));
  const std::vector<TableRow> short_row = {TableRow{std::string("ggk")}};
  EXPECT_TRUE(
      contains(error_message([&] { file.append_rows("t", short_row); }), "1 values for 5 columns"));
  const auto rows = file.read_table("t");
  ASSERT_EQ(rows.size(), 2U);
  EXPECT_EQ(std::get<std::string>(rows[1][0]), "gaussian");

  const std::vector<TableColumn> duplicate = {{"a", ColumnType::kInt32, 0},
                                              {"a", ColumnType::kFloat64, 0}};
  EXPECT_TRUE(contains(error_message([&] { file.create_table("dup", duplicate); }),
                       "duplicate column 'a'"));
  std::vector<TableRow> with_nul = {summary_row(1)};
  with_nul[0][4] = std::string("a\0b", 3);  // in the variable-length column
  EXPECT_TRUE(contains(error_message([&] { file.append_rows("t", with_nul); }),
                       "column 'status': string contains a NUL character"));
  file.write_vector("not_a_table", std::vector<double>{1.0});
  EXPECT_TRUE(
      contains(error_message([&] { file.append_rows("not_a_table", good); }), "not a table"));
}

TEST_F(Hdf5FileTest, WritingAnExistingPathIsAnErrorNamingThePath) {
  auto file = Hdf5File::create(file_path());
  file.write_vector("/maze/run_000/samples/rewards", std::vector<double>{1.0});
  EXPECT_TRUE(contains(error_message([&] {
                         file.write_vector("/maze/run_000/samples/rewards",
                                           std::vector<double>{2.0});
                       }),
                       "'/maze/run_000/samples/rewards': already exists"));
  EXPECT_TRUE(contains(error_message([&] { file.create_group("maze/run_000"); }),
                       "'/maze/run_000': already exists"));
  EXPECT_TRUE(
      contains(error_message([&] { file.write_strings("/maze", std::vector<std::string>{}); }),
               "'/maze': already exists"));
  EXPECT_TRUE(
      contains(error_message([&] { file.create_table("/maze/run_000", summary_columns()); }),
               "already exists"));
  // Below a dataset nothing can be created.
  EXPECT_TRUE(contains(error_message([&] {
                         file.write_vector("/maze/run_000/samples/rewards/x",
                                           std::vector<double>{});
                       }),
                       "'/maze/run_000/samples/rewards/x': parent '/maze/run_000/samples/rewards' "
                       "is not a group"));
  EXPECT_EQ(file.read_vector<double>("/maze/run_000/samples/rewards"), std::vector<double>{1.0});
}

TEST_F(Hdf5FileTest, ExistsChecksEveryComponent) {
  auto file = Hdf5File::create(file_path());
  EXPECT_TRUE(file.exists("/"));
  EXPECT_FALSE(file.exists("/a/b/c"));
  file.write_vector("/a/b/c", std::vector<double>{1.0});
  EXPECT_TRUE(file.exists("/a"));
  EXPECT_TRUE(file.exists("a/b"));
  EXPECT_TRUE(file.exists("/a/b/c/"));
  EXPECT_FALSE(file.exists("/a/b/c/d"));
  EXPECT_FALSE(file.exists("/a/x/c"));
  EXPECT_TRUE(file.exists("/a//b/c"));  // an empty component is skipped
  EXPECT_FALSE(file.exists("/a//x"));
}

TEST_F(Hdf5FileTest, RemoveDiscardsAGroupWhichCanThenBeRecreated) {
  auto file = Hdf5File::create(file_path());
  file.write_vector("/maze/run_001/samples/rewards", std::vector<double>{1.0, 2.0});
  file.write_string_attribute("/maze/run_001", "note", "incomplete");
  file.write_vector("/maze/run_002/samples/rewards", std::vector<double>{9.0});
  file.remove("/maze/run_001");
  EXPECT_FALSE(file.exists("/maze/run_001"));
  EXPECT_FALSE(file.exists("/maze/run_001/samples/rewards"));
  EXPECT_TRUE(file.exists("/maze/run_002/samples/rewards"));
  file.write_vector("/maze/run_001/samples/rewards", std::vector<double>{3.0});
  EXPECT_FALSE(file.has_attribute("/maze/run_001", "note"));
  EXPECT_EQ(file.read_vector<double>("/maze/run_001/samples/rewards"), std::vector<double>{3.0});
  EXPECT_TRUE(contains(error_message([&] { file.remove("/maze/run_003"); }),
                       "'/maze/run_003': no such object"));
  EXPECT_TRUE(contains(error_message([&] { file.remove("/"); }), "root"));
}

TEST_F(Hdf5FileTest, OpeningAMissingFileNamesThePath) {
  const fs::path missing = file_path("missing.h5");
  const std::string message = error_message([&] { Hdf5File::open_read_only(missing); });
  EXPECT_TRUE(contains(message, missing.string()));
  EXPECT_TRUE(contains(message, "no such file"));
  EXPECT_TRUE(
      contains(error_message([&] { Hdf5File::open_read_write(missing); }), missing.string()));
}

TEST_F(Hdf5FileTest, OpeningADirectoryNamesThePath) {
  const std::string message = error_message([&] { Hdf5File::open_read_only(dir_); });
  EXPECT_TRUE(contains(message, dir_.string()));
  EXPECT_TRUE(contains(message, "it is a directory"));
  EXPECT_TRUE(
      contains(error_message([&] { Hdf5File::create(dir_, Hdf5File::CreateMode::kTruncate); }),
               dir_.string()));
}

TEST_F(Hdf5FileTest, OpeningANonHdf5FileNamesThePath) {
  const fs::path text = file_path("job.toml");
  std::ofstream(text) << "name = \"maze\"\n";
  const std::string message = error_message([&] { Hdf5File::open_read_write(text); });
  EXPECT_TRUE(contains(message, text.string()));
  EXPECT_TRUE(contains(message, "not an HDF5 file"));
}

TEST_F(Hdf5FileTest, CreateRefusesAnExistingFileUnlessTruncating) {
  {
    auto file = Hdf5File::create(file_path());
    file.write_vector("x", std::vector<double>{1});
  }
  const std::string message = error_message([&] { Hdf5File::create(file_path()); });
  EXPECT_TRUE(contains(message, file_path().string()));
  EXPECT_TRUE(contains(message, "file exists"));
  EXPECT_TRUE(Hdf5File::open_read_only(file_path()).exists("x"));
  auto file = Hdf5File::create(file_path(), Hdf5File::CreateMode::kTruncate);
  EXPECT_FALSE(file.exists("x"));
  EXPECT_TRUE(contains(error_message([&] { Hdf5File::create(dir_ / "no" / "such" / "dir.h5"); }),
                       "no such directory"));
}

// Hdf5File::Object answers as the by-path calls of the same name, on every kind
// of object a results file holds (the digest and the schema's descriptions walk
// through it), and skips soft links as hard_link_address does.
TEST_F(Hdf5FileTest, AnObjectHeldOpenReadsAsTheByPathCalls) {
  {
    auto file = Hdf5File::create(file_path());
    file.create_group("/g/empty");
    file.write_string_attribute("/g", "job", "name = \"maze\"");
    file.write_int64_array_attribute("/g", "shape", std::vector<std::int64_t>{3, 4});
    file.write_vector("/g/d", std::vector<double>{1.5, -2.0, std::nan("")});
    file.write_double_attribute("/g/d", "scale", 0.25);
    file.write_matrix("/g/m", 2, 3, std::vector<std::int32_t>{1, 2, 3, 4, 5, 6});
    file.write_strings("/g/s", std::vector<std::string>{"a", "θ"});
    file.write_vector("/g/none", std::vector<double>{});
    file.create_table("/g/t", summary_columns(), 4);
    file.append_rows("/g/t", std::vector<TableRow>{summary_row(1), summary_row(2)});
  }
  {
    const hid_t f = H5Fopen(file_path().c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    EXPECT_GE(H5Lcreate_soft("/g/d", f, "/g/soft", H5P_DEFAULT, H5P_DEFAULT), 0);
    H5Fclose(f);
  }
  const auto file = Hdf5File::open_read_only(file_path());
  EXPECT_FALSE(file.open_hard_link("/g/soft").has_value());
  const std::optional<Hdf5File::Object> group = file.open_hard_link("g/");
  ASSERT_TRUE(group.has_value());
  EXPECT_EQ(group->path(), "/g");
  EXPECT_EQ(group->kind(), Hdf5File::ObjectKind::kGroup);
  EXPECT_EQ(group->member_names(), file.member_names("/g"));
  EXPECT_EQ(group->attribute_names(), (std::vector<std::string>{"job", "shape"}));
  for (const std::string& name : group->attribute_names()) {
    EXPECT_EQ(group->read_attribute_values(name), file.read_attribute_values("/g", name)) << name;
  }
  int datasets = 0;
  for (const std::string& member : group->member_names()) {
    const std::optional<Hdf5File::Object> object = group->hard_member(member);
    if (member == "soft") {
      EXPECT_FALSE(object.has_value());
      continue;
    }
    ASSERT_TRUE(object.has_value()) << member;
    const std::string path = "/g/" + member;
    EXPECT_EQ(object->path(), path);
    EXPECT_EQ(object->kind(), file.object_kind(path)) << member;
    EXPECT_EQ(object->attribute_names(), file.attribute_names(path)) << member;
    for (const std::string& name : object->attribute_names()) {
      EXPECT_EQ(object->read_attribute_values(name), file.read_attribute_values(path, name));
    }
    if (object->kind() != Hdf5File::ObjectKind::kDataset) continue;
    ++datasets;
    EXPECT_EQ(object->dataset_shape(), file.dataset_shape(path)) << member;
    EXPECT_EQ(object->read_values(), file.read_values(path)) << member;
    const std::vector<std::string> skip = {"run", "status"};
    EXPECT_EQ(object->read_values(skip), file.read_values(path, skip)) << member;
  }
  EXPECT_EQ(datasets, 5);
  const Hdf5File::Values table =
      file.open_hard_link("/g/t")->read_values(std::vector<std::string>{"status"});
  EXPECT_EQ(table.parts.size(), 4u);  // skipping a member reads the others only
  EXPECT_TRUE(contains(error_message([&] { group->read_attribute_values("missing"); }),
                       "open attribute 'missing' of '/g'"));
  EXPECT_TRUE(contains(error_message([&] { file.open_hard_link("/g/nowhere"); }),
                       "'/g/nowhere': no such object"));
}

TEST_F(Hdf5FileTest, AnObjectHeldOpenWritesStringAttributesOnce) {
  {
    auto file = Hdf5File::create(file_path());
    file.write_vector("/g/d", std::vector<double>{1.0});
    std::optional<Hdf5File::Object> dataset = file.open_hard_link("/g/d");
    ASSERT_TRUE(dataset.has_value());
    dataset->write_string_attribute("units", "m/s²");
    EXPECT_TRUE(contains(error_message([&] { dataset->write_string_attribute("units", "m"); }),
                         "attribute 'units' already exists"));
    EXPECT_TRUE(contains(error_message([&] {
                           dataset->write_string_attribute("x", {"a\0b", 3});
                         }),
                         "NUL"));
  }
  auto file = Hdf5File::open_read_only(file_path());
  EXPECT_EQ(file.read_string_attribute("/g/d", "units"), "m/s²");
  EXPECT_EQ(file.attribute_names("/g/d"), std::vector<std::string>{"units"});
  std::optional<Hdf5File::Object> dataset = file.open_hard_link("/g/d");
  EXPECT_TRUE(
      contains(error_message([&] { dataset->write_string_attribute("dims", "x"); }), "read-only"));
}

TEST_F(Hdf5FileTest, ReadOnlyFileRefusesWrites) {
  {
    auto file = Hdf5File::create(file_path());
    file.create_group("g");
  }
  auto file = Hdf5File::open_read_only(file_path());
  EXPECT_TRUE(file.read_only());
  EXPECT_TRUE(contains(error_message([&] { file.write_vector("x", std::vector<double>{1}); }),
                       "read-only"));
  EXPECT_TRUE(contains(error_message([&] { file.remove("g"); }), "read-only"));
  EXPECT_TRUE(
      contains(error_message([&] { file.write_int64_attribute("/", "a", 1); }), "read-only"));
}

TEST_F(Hdf5FileTest, ChunkedDatasetsAreCompressed) {
  const std::vector<double> zeros(1000000, 0.0);  // 8 MB raw
  {
    auto file = Hdf5File::create(file_path());
    file.write_vector("zeros", zeros);
  }
  EXPECT_LT(fs::file_size(file_path()), 200000U);
  {
    auto file = Hdf5File::create(file_path("raw.h5"));
    file.set_gzip_level(0);
    file.write_vector("zeros", zeros);
  }
  EXPECT_GT(fs::file_size(file_path("raw.h5")), 8000000U);
  auto file = Hdf5File::create(file_path("x.h5"));
  EXPECT_THROW(file.set_gzip_level(10), std::invalid_argument);
}

TEST_F(Hdf5FileTest, MovedFileKeepsWorking) {
  auto first = Hdf5File::create(file_path());
  Hdf5File second = std::move(first);
  second.write_vector("x", std::vector<double>{1});
  auto third = Hdf5File::create(file_path("other.h5"));
  third = std::move(second);
  EXPECT_EQ(third.path(), file_path());
  EXPECT_EQ(third.read_vector<double>("x"), std::vector<double>{1});
}

// The commit protocol of the header: write a run under a staging path, flush,
// move it to its final path, append its summary row, flush.
void commit_run(Hdf5File& file, int run) {
  const std::string staging = "/.staging/maze/run_" + std::to_string(run);
  for (int part = 0; part < 4; ++part) {
    file.write_vector(staging + "/samples/part_" + std::to_string(part),
                      std::vector<double>(2000, run + 0.25 * part));
  }
  file.flush();
  file.move(staging, "/maze/run_" + std::to_string(run));
  const std::vector<TableRow> row = {summary_row(run)};
  file.append_rows("/maze/summary", row);
  file.flush();
}

// Every committed run is whole; rows appended after the last flush may or may
// not have reached the disk, but every flushed row has.
void expect_runs(const Hdf5File& file, int runs) {
  for (int run = 0; run < runs; ++run) {
    for (int part = 0; part < 4; ++part) {
      EXPECT_EQ(file.read_vector<double>("/maze/run_" + std::to_string(run) + "/samples/part_" +
                                         std::to_string(part)),
                std::vector<double>(2000, run + 0.25 * part));
    }
  }
  EXPECT_FALSE(file.exists("/maze/run_" + std::to_string(runs)));
  const std::vector<TableRow> rows = file.read_table("/maze/summary");
  ASSERT_GE(rows.size(), static_cast<std::size_t>(runs));
  for (int run = 0; run < runs; ++run) EXPECT_EQ(rows[run], summary_row(run)) << "row " << run;
  for (std::size_t r = runs; r < rows.size(); ++r) {  // a row of a run in flight at the kill
    EXPECT_TRUE(rows[r] == summary_row(runs) || rows[r] == summary_row(runs - 1)) << "row " << r;
  }
}

// A writer killed between flushes, in the middle of writing the next run,
// leaves a file with every flushed run and summary row; resuming detaches the
// staging leftovers and commits the lost run again.
TEST_F(Hdf5FileTest, FlushedRunsSurviveKillMinus9) {
  const fs::path path = file_path();
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    try {
      auto file = Hdf5File::create(path);
      file.write_string_attribute("/", "job", "name = \"maze\"");
      file.create_table("/maze/summary", summary_columns(), 4);
      file.flush();
      for (int run = 0; run < 6; ++run) commit_run(file, run);
      // In flight: part of run 6 and a summary row (rewriting a flushed chunk).
      file.write_vector("/.staging/maze/run_6/samples/part_0", std::vector<double>(2000, 6.0));
      const std::vector<TableRow> row = {summary_row(6)};
      file.append_rows("/maze/summary", row);
    } catch (...) {
      ::_exit(1);
    }
    ::raise(SIGKILL);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status)) << "child failed before the kill";
  ASSERT_EQ(WTERMSIG(status), SIGKILL);
  {
    const auto file = Hdf5File::open_read_only(path);
    EXPECT_EQ(file.read_string_attribute("/", "job"), "name = \"maze\"");
    expect_runs(file, 6);
  }
  {
    auto file = Hdf5File::open_read_write(path);
    if (file.exists("/.staging")) file.detach("/.staging");
    commit_run(file, 6);
  }
  expect_runs(Hdf5File::open_read_only(path), 7);
}

TEST_F(Hdf5FileTest, MoveRenamesAndCreatesParents) {
  auto file = Hdf5File::create(file_path());
  file.write_vector("/.staging/run_000/samples/rewards", std::vector<double>{1.0, 2.0});
  file.write_int64_attribute("/.staging/run_000", "seed", 5);
  file.move("/.staging/run_000", "/maze/run_000");
  EXPECT_FALSE(file.exists("/.staging/run_000"));
  EXPECT_EQ(file.read_vector<double>("/maze/run_000/samples/rewards"),
            (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(file.read_int64_attribute("/maze/run_000", "seed"), 5);
  file.write_vector("/.staging/run_001/x", std::vector<double>{});
  EXPECT_TRUE(contains(error_message([&] { file.move("/.staging/run_001", "/maze/run_000"); }),
                       "'/maze/run_000': already exists"));
  EXPECT_TRUE(contains(error_message([&] { file.move("/nowhere", "/maze/run_009"); }),
                       "'/nowhere': no such object"));
  EXPECT_TRUE(file.exists("/.staging/run_001/x"));
}

TEST_F(Hdf5FileTest, DetachUnlinksWithoutTouchingWhatIsBelow) {
  {
    auto file = Hdf5File::create(file_path());
    file.write_vector("/.staging/run_003/samples/rewards", std::vector<double>(100, 1.0));
    file.write_vector("/maze/run_000/samples/rewards", std::vector<double>{7.0});
    file.detach("/.staging/run_003");
    EXPECT_FALSE(file.exists("/.staging/run_003"));
    EXPECT_TRUE(file.exists("/.staging"));
    file.write_vector("/.staging/run_003/samples/rewards", std::vector<double>{3.0});
    EXPECT_THROW(file.detach("/"), std::runtime_error);
    EXPECT_THROW(file.detach("/missing"), std::runtime_error);
  }
  const auto file = Hdf5File::open_read_only(file_path());
  EXPECT_EQ(file.read_vector<double>("/.staging/run_003/samples/rewards"),
            std::vector<double>{3.0});
  EXPECT_EQ(file.read_vector<double>("/maze/run_000/samples/rewards"), std::vector<double>{7.0});
}

}  // namespace
}  // namespace ggk::engine
