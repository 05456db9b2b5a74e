#pragma once
// Hdf5File: a small RAII wrapper over the HDF5 C API for the result store.
//
// Paths are HDF5 object paths inside the file ("/maze/run_000/samples/rewards");
// a leading '/' is optional, "/" is the root group. Every write creates a new
// object, creating missing parent groups on the way; writing to a path that
// already exists is an error naming the path. Data is discarded only by
// remove() or detach() of a whole object (the engine drops an incomplete run
// before redoing it); space freed by remove() is reused only while the file
// stays open (h5repack compacts a file).
//
// Layout on disk, chosen so that h5py/pandas read it without help:
//  - numeric datasets are little-endian IEEE/two's complement, 1-D or 2-D
//    row-major; non-empty ones are chunked with shuffle + gzip (level
//    gzip_level(), default 4) + a Fletcher32 checksum per chunk; empty ones (a 0
//    in the shape) are contiguous;
//  - string datasets and string attributes are variable-length UTF-8; readers
//    also accept fixed-length strings;
//  - a sparse matrix is a CSR triple group <path>/{indptr int64, indices int32,
//    data double} with attribute shape = int64[2] {rows, cols};
//  - a table is a 1-D extendable, chunked, checksummed, uncompressed dataset (see
//    "Crashes") of a compound type (int32, int64, double and variable-length
//    UTF-8 string columns, what h5py writes for str), so that
//    pandas.DataFrame(h5py.File(f)[path][:]) reads it in one call (h5py hands
//    the strings of a compound over as bytes: results/README.md decodes them);
//    readers also accept the fixed-length string columns of older files.
// Default library format bounds (files readable by HDF5 >= 1.8, h5py on
// Debian 12). The per-chunk checksums make damage to the numbers an error on
// reading (ggk verify reads every dataset), not wrong values. The 1.8/1.10
// formats would add checksums to metadata too, but were tried and left: with
// them a killed writer's file (1.10) does not open without h5clear, and
// HDF5 1.10.8's H5Ocopy crashes on dense string attributes (1.8).
// Variable-length strings live in the global heap, which no filter covers.
// What no checksum covers (names, attributes, shapes) a run's digest does
// (store/run_digest.hpp). HDF5 1.10.8 itself can crash (SIGSEGV in
// H5Aiterate) on some damaged object headers: about 1 in 40 files with 1-8
// random bytes overwritten (scripts/stress_kills.sh hostile_results).
//
// Crashes: HDF5 1.10 has no journal. After a kill -9 between two flushes the
// file opens with everything written up to the last flush() that returned;
// what was written after it may or may not be there. A kill *during* a flush
// can leave what that flush was writing, and the group linking to it,
// unreadable (2-4% of random kills in a stress test that flushes all the
// time; in the engine the exposure is the fraction of time spent flushing).
// So commit a run in two steps, which puts only a staging group at risk:
//   1. write the run under a staging path (/.staging/maze/run_003), flush();
//   2. move() it to its final path (/maze/run_003), append its summary row,
//      flush().
// On resume, detach() whatever is left under the staging path: it may be
// damaged, and remove() then fails. With this protocol every committed run
// stayed readable in 300 random kills of the stress test.
// Tables are chunked but not compressed: appending to a compressed chunk
// rewrites it in place, and random kills showed that this can destroy rows
// that an earlier flush had written.
//
// Errors: every failure throws std::runtime_error naming the file, the object
// path and HDF5's own reason (collected from its error stack; HDF5's automatic
// printing to stderr is switched off in every thread that uses this class).
//
// Thread-safety: none; one thread at a time per object. HDF5 itself may not be
// entered concurrently unless built thread-safe (Debian 12's is, with one
// global lock, so parallel calls would only queue up; other builds are not).
// The engine therefore makes every HDF5 call on StoreWriter's single thread.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <Eigen/SparseCore>

namespace ggk::engine {

// Row-major 2-D array as read back from a file: element (i, j) is data[i * cols + j].
template <class T>
struct RowMajorArray {
  std::int64_t rows = 0;
  std::int64_t cols = 0;
  std::vector<T> data;
};

// Compressed sparse row matrix as stored in a file: row i holds the entries
// indptr[i] .. indptr[i + 1] - 1 of indices (columns) and data (values).
struct CsrArrays {
  std::int64_t rows = 0;
  std::int64_t cols = 0;
  std::vector<std::int64_t> indptr;  // rows + 1 entries, indptr[0] = 0
  std::vector<std::int32_t> indices;
  std::vector<double> data;
};

// Same storage order and index type as ggk::kernels::SparseRowMatrix.
using CsrMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, std::int32_t>;

enum class ColumnType { kInt32, kInt64, kFloat64, kString };

// One column of a table. Strings are variable-length UTF-8 (string_size 0), or
// fixed-length: string_size bytes of UTF-8, NUL-padded, a longer value an error
// (no silent truncation); the engine writes variable-length ones, fixed ones
// are read from older files.
struct TableColumn {
  std::string name;
  ColumnType type = ColumnType::kFloat64;
  std::size_t string_size = 0;  // kString: bytes, or 0 for variable length; ignored otherwise

  bool operator==(const TableColumn&) const = default;
};

// One cell / one row of a table; a row holds one value per column, in column
// order, each of the column's type.
using TableValue = std::variant<std::int32_t, std::int64_t, double, std::string>;
using TableRow = std::vector<TableValue>;

class Hdf5File {
 public:
  enum class CreateMode {
    kFailIfExists,  // an existing file is an error
    kTruncate,      // an existing file is replaced
  };

  // Creates a new file (opened read-write).
  static Hdf5File create(const std::filesystem::path& path,
                         CreateMode mode = CreateMode::kFailIfExists);
  static Hdf5File open_read_only(const std::filesystem::path& path);
  static Hdf5File open_read_write(const std::filesystem::path& path);
  // Like open(), but while another process holds HDF5's lock on the file (a
  // writer between two runs, or readers) tries again for up to `patience`.
  static Hdf5File open_waiting_for_lock(const std::filesystem::path& path, bool read_only,
                                        std::chrono::milliseconds patience);
  // Opens read-write again a file this process writes and closed between two
  // commits so that others could read it: waits up to 3 s for readers that
  // hold HDF5's lock, then opens without it (the caller holds ggk's own output
  // lock, so there is no second writer; a reader that keeps the file open keeps
  // its old view and sees the new runs when it opens the file again).
  static Hdf5File reopen_for_writer(const std::filesystem::path& path);

  // In-memory files (HDF5's core driver, nothing on disk), to move a group between
  // processes: create one, write into it, take its bytes with file_image(); the
  // receiver opens the bytes read-only with open_image() and copy_from()s what it
  // needs. `name` names the file in messages.
  static Hdf5File create_in_memory(const std::string& name);
  std::vector<unsigned char> file_image();  // flushes first
  static Hdf5File open_image(std::span<const unsigned char> image, const std::string& name);
  // True for a file made by create_in_memory() or open_image().
  bool in_memory() const;

  Hdf5File(Hdf5File&& other) noexcept;
  Hdf5File& operator=(Hdf5File&& other) noexcept;
  Hdf5File(const Hdf5File&) = delete;
  Hdf5File& operator=(const Hdf5File&) = delete;
  ~Hdf5File();  // closes the file; errors on close are dropped (call close() to see them)
  // Closes the file now (writing what is buffered); throws when HDF5 cannot.
  // The object is then closed whatever happened; a second close() does nothing.
  void close();
  // For a file whose write failed (a full disk): lets go of it without closing.
  // Closing would write HDF5's cached metadata, which may describe data that
  // never reached the disk, and leave a file that no longer opens; abandoned,
  // the file stays as its last successful flush() left it, as after a kill
  // (which --resume handles). The handle stays open until the process exits.
  void abandon() noexcept { id_ = -1; }
  // The file was renamed on disk while open (the handle follows the file): name
  // it so in messages from now on.
  void renamed_to(const std::filesystem::path& path);

  const std::filesystem::path& path() const { return path_; }
  bool read_only() const { return read_only_; }

  // Compression of chunked datasets written from now on: 0 (none) .. 9.
  void set_gzip_level(int level);
  int gzip_level() const { return gzip_level_; }

  // Writes every buffer and all metadata of the file to disk (H5Fflush). See
  // "Crashes" above for how to commit a run so that a kill cannot damage it.
  void flush();

  // True when every component of path exists ("/" always exists).
  bool exists(std::string_view path) const;
  // Creates a group and any missing parents; an existing path is an error.
  void create_group(std::string_view path);
  // Unlinks the object at path (a whole group with everything below it) and
  // frees its space for reuse. This reads every object below path, so it fails
  // on objects that a kill during a flush damaged; detach() those instead.
  void remove(std::string_view path);
  // Unlinks the object at path without reading anything below it: the object
  // stays in the file, unreachable, and its space is not reused. For leftovers
  // of a killed writer (a staging group), which may be damaged.
  void detach(std::string_view path);
  // Renames (moves) the object at `from` to the new path `to`, creating
  // missing parents of `to`; only the link changes, the object is not read.
  void move(std::string_view from, std::string_view to);
  // Copies the object at source_path of `source` (another open file, or this one)
  // to destination_path here, with everything below it, creating missing parents;
  // dataset storage (chunks, filters) and attributes are copied as they are.
  void copy_from(const Hdf5File& source, std::string_view source_path,
                 std::string_view destination_path);

  // Introspection, for tools that walk a whole file (ggk diff, merge).
  enum class ObjectKind { kGroup, kDataset, kOther };
  ObjectKind object_kind(std::string_view path) const;
  // The address of the object a hard link names (equal addresses: the same
  // object, reached twice: a cycle or a second link); nullopt when `path` is a
  // soft, external or user-defined link, which a walk must not follow (a link to
  // the file itself, or to an ancestor, never ends).
  std::optional<std::uint64_t> hard_link_address(std::string_view path) const;
  // Names of a group's members / an object's attributes, sorted by name.
  std::vector<std::string> member_names(std::string_view group_path) const;
  std::vector<std::string> attribute_names(std::string_view object_path) const;
  // The values of a dataset or attribute in a canonical form to compare files by:
  // `type` describes the stored type and shape; strings (fixed or variable length,
  // alone or as compound members) are decoded; numbers are their native bytes.
  // Members of a compound type named in `skip_members` are left out.
  // `parts` says how to read `bytes` and `strings` element by element: a plain
  // dataset or attribute is one part, a compound one part per member (member
  // after member, each holding every row's element of that member).
  // kOther: any other type (enum, bitfield, ...), compared as bytes.
  enum class ElementClass { kSigned, kUnsigned, kFloat, kString, kOther };
  struct Part {
    std::string member;  // empty for a plain dataset or attribute
    ElementClass element_class = ElementClass::kFloat;
    std::size_t element_size = 0;  // bytes per element in `bytes`; 0 for strings
    bool operator==(const Part&) const = default;
  };
  struct Values {
    std::string type;
    std::vector<std::int64_t> shape;
    std::vector<unsigned char> bytes;  // numbers, row-major, native layout
    std::vector<std::string> strings;  // decoded strings, in element order
    std::vector<Part> parts;
    bool operator==(const Values&) const = default;
  };
  Values read_values(std::string_view dataset_path,
                     std::span<const std::string> skip_members = {}) const;
  Values read_attribute_values(std::string_view object_path, std::string_view name) const;

  // Shape of the dataset at path (empty for a scalar dataset).
  std::vector<std::int64_t> dataset_shape(std::string_view path) const;

  // An object held open, for walks over a whole tree that read or describe every
  // part of it (a run's digest, its datasets' descriptions): its members,
  // attributes, shape and values are reached through the open object, never by
  // looking a path up again (every by-path call above walks its path anew, which
  // made the walks cost most of the writer's time). Each call answers as the
  // by-path call of the same name on path(). Valid while the file stays open.
  class Object {
   public:
    Object(Object&& other) noexcept;
    Object& operator=(Object&&) = delete;
    Object(const Object&) = delete;
    Object& operator=(const Object&) = delete;
    ~Object();

    const std::string& path() const { return path_; }
    ObjectKind kind() const;
    std::vector<std::string> member_names() const;  // a group's, sorted by name
    // Member `name` of this group, opened; nullopt when its link is not a hard
    // link (hard_link_address).
    std::optional<Object> hard_member(std::string_view name) const;
    std::vector<std::string> attribute_names() const;  // sorted by name
    Values read_attribute_values(std::string_view name) const;
    std::vector<std::int64_t> dataset_shape() const;
    Values read_values(std::span<const std::string> skip_members = {}) const;
    // As Hdf5File::write_string_attribute (the file must be open for writing).
    void write_string_attribute(std::string_view name, std::string_view value);

   private:
    friend class Hdf5File;
    Object(const Hdf5File& file, std::string path, std::int64_t id);

    const Hdf5File* file_;
    std::string path_;
    std::int64_t id_;  // the hid_t of the open object; -1 once moved from
  };
  // The object at `path`, opened; nullopt when `path` names a soft, external or
  // user-defined link (as hard_link_address).
  std::optional<Object> open_hard_link(std::string_view path) const;

  // 1-D numeric datasets.
  void write_vector(std::string_view path, std::span<const double> values);
  void write_vector(std::string_view path, std::span<const float> values);
  void write_vector(std::string_view path, std::span<const std::int32_t> values);
  void write_vector(std::string_view path, std::span<const std::int64_t> values);
  void write_vector(std::string_view path, std::span<const std::uint8_t> values);
  // T is one of the five types above and must match the stored element type
  // exactly (class, size, signedness); the dataset must be 1-D.
  template <class T>
  std::vector<T> read_vector(std::string_view path) const;

  // 2-D row-major numeric datasets; values.size() must equal rows * cols.
  void write_matrix(std::string_view path, std::int64_t rows, std::int64_t cols,
                    std::span<const double> values);
  void write_matrix(std::string_view path, std::int64_t rows, std::int64_t cols,
                    std::span<const std::int32_t> values);
  template <class T>  // double or std::int32_t
  RowMajorArray<T> read_matrix(std::string_view path) const;

  // 1-D string datasets (UTF-8, no embedded NUL characters).
  void write_strings(std::string_view path, std::span<const std::string> values);
  std::vector<std::string> read_strings(std::string_view path) const;

  // Attributes on the object at object_path ("/" for the file root). Writing an
  // attribute that exists is an error; remove_attribute() first to replace one.
  bool has_attribute(std::string_view object_path, std::string_view name) const;
  void remove_attribute(std::string_view object_path, std::string_view name);
  void write_string_attribute(std::string_view object_path, std::string_view name,
                              std::string_view value);
  void write_double_attribute(std::string_view object_path, std::string_view name, double value);
  void write_int64_attribute(std::string_view object_path, std::string_view name,
                             std::int64_t value);
  void write_int64_array_attribute(std::string_view object_path, std::string_view name,
                                   std::span<const std::int64_t> values);
  std::string read_string_attribute(std::string_view object_path, std::string_view name) const;
  double read_double_attribute(std::string_view object_path, std::string_view name) const;
  std::int64_t read_int64_attribute(std::string_view object_path, std::string_view name) const;
  std::vector<std::int64_t> read_int64_array_attribute(std::string_view object_path,
                                                       std::string_view name) const;

  // Sparse matrix as a CSR triple group (layout above). The arrays are checked:
  // indptr has rows + 1 non-decreasing entries from 0 to nnz, column indices lie
  // in [0, cols). values_name names the value dataset (the graph stores
  // "weights"); the reader must pass the same name.
  void write_csr(std::string_view path, std::int64_t rows, std::int64_t cols,
                 std::span<const std::int64_t> indptr, std::span<const std::int32_t> indices,
                 std::span<const double> values, std::string_view values_name = "data");
  void write_csr(std::string_view path, const CsrMatrix& matrix,
                 std::string_view values_name = "data");
  CsrArrays read_csr(std::string_view path, std::string_view values_name = "data") const;
  CsrMatrix read_csr_matrix(std::string_view path, std::string_view values_name = "data") const;

  // Tables: create an empty table, then append rows in as many batches as
  // needed (each batch is one extend + one write). chunk_rows sets the chunk
  // size (rows per chunk, >= 1). The column list of an existing table is read
  // from the file, so appending works after reopening it.
  void create_table(std::string_view path, std::span<const TableColumn> columns,
                    std::int64_t chunk_rows = 256);
  void append_rows(std::string_view path, std::span<const TableRow> rows);
  std::vector<TableColumn> read_table_columns(std::string_view path) const;
  std::vector<TableRow> read_table(std::string_view path) const;

 private:
  Hdf5File(std::filesystem::path path, std::int64_t id, bool read_only);
  static Hdf5File open(const std::filesystem::path& path, bool read_only);

  // Throws unless the file is writable and object_path does not exist yet.
  void require_new_object(std::string_view object_path) const;
  // The absolute path of a new object at `path` (relative to the root), after
  // require_new_object.
  std::string new_object_path(std::string_view path) const;

  std::filesystem::path path_;
  std::int64_t id_ = -1;  // the hid_t of the open file; -1 once moved from
  bool read_only_ = false;
  int gzip_level_ = 4;
};

}  // namespace ggk::engine
