#pragma once
// A small RAII layer over the HDF5 C API (HighFive is not packaged in Debian 12): files, groups, datasets,
// dataspaces and attributes are move-only handles closed in their destructors, whole 1-D / 2-D arrays of
// double, int32 and int64 are written and read in one call, and every failure becomes a std::runtime_error
// that names the file, the object and HDF5's own reason. HDF5's automatic printing of its error stack to
// stderr is switched off inside this layer, since the exception carries the message instead.
//
// A file opened with FileOptions::all_ranks is one file of every rank of an MPI run (MPI-IO). Every rank
// then makes the same calls with the same arguments (creating groups and datasets, attributes, links,
// flush, close), and write() / write_strings() store rank 0's values; write_rows() is how each rank stores
// its own rows of one dataset (collective). In a serial build or on one rank the option changes nothing.
//
// Files use HDF5's default (oldest) format on purpose: the 1.10 "latest" format marks a file as open for
// writing in its superblock, and after a killed run every reader then refuses it until `h5clear -s`.
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace debris::h5 {

using Shape = std::vector<std::size_t>;

/// The element types stored: double, int32 (int) and int64 (long, std::int64_t).
template <class T>
concept Element = std::same_as<T, double> || std::same_as<T, std::int32_t> || std::same_as<T, std::int64_t>;

/// A whole dataset read back: values in row-major order and its shape ({} for a scalar dataset).
template <Element T>
struct Array {
  std::vector<T> values;
  Shape shape;
};

/// Owns one HDF5 identifier (hid_t) and closes it with the matching H5?close; move-only.
class Handle {
 public:
  using Closer = int (*)(std::int64_t);
  Handle() = default;
  Handle(std::int64_t id, Closer closer) : id_(id), closer_(closer) {}
  Handle(Handle&& o) noexcept : id_(o.id_), closer_(o.closer_) { o.id_ = -1; }
  Handle& operator=(Handle&& o) noexcept;
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }

  std::int64_t id() const { return id_; }
  bool valid() const { return id_ >= 0; }
  /// Closes now; returns false if HDF5 reported an error (destructors ignore it, close() paths check it).
  bool reset() noexcept;

 private:
  std::int64_t id_ = -1;
  Closer closer_ = nullptr;
};

class Dataspace {
 public:
  static Dataspace scalar();
  static Dataspace simple(const Shape& shape);
  /// Wraps an identifier returned by H5Dget_space / H5Aget_space.
  explicit Dataspace(Handle h) : h_(std::move(h)) {}
  std::int64_t id() const { return h_.id(); }
  /// {} for a scalar dataspace.
  Shape shape() const;
  std::size_t elements() const;

 private:
  Handle h_;
};

/// The rows of a dataset of `shape` (shape[0] rows, each of the product of the other dimensions) that one
/// process writes: `rows` strictly increasing, selected as blocks of consecutive rows. Made once and given
/// to write_rows() for every dataset of that shape and those rows: selecting thousands of blocks costs
/// HDF5 more than writing them. std::invalid_argument for rows out of order or range, or a scalar shape.
class RowSelection {
 public:
  RowSelection(std::span<const std::int64_t> rows, const Shape& shape);
  const Shape& shape() const { return shape_; }
  std::size_t rows() const { return rows_; }
  std::size_t row_width() const { return width_; }
  /// The file dataspace of `shape` with the rows selected.
  std::int64_t id() const { return space_.id(); }

 private:
  Shape shape_;
  std::size_t rows_ = 0, width_ = 1;
  Dataspace space_;
};

class Dataset {
 public:
  Dataset(Handle h, std::string file, std::string path) : h_(std::move(h)), file_(std::move(file)), path_(std::move(path)) {}
  std::int64_t id() const { return h_.id(); }
  const std::string& path() const { return path_; }
  Shape shape() const;
  /// The whole dataset; std::runtime_error if its stored type does not fit T without loss.
  template <Element T>
  Array<T> read() const;

 private:
  Handle h_;
  std::string file_, path_;
};

class Group;

struct GroupOptions {
  /// For a group that grows to many members: sizes its heap of member names up front (about 8 bytes per
  /// short name), so adding a member rewrites that heap in place instead of moving it.
  std::size_t reserved_name_bytes = 0;
  /// For a group of a few members: keeps them in the group's own header (HDF5 >= 1.8 "compact" links),
  /// so the group costs no index of its own. Not together with reserved_name_bytes.
  bool small = false;
};

/// What File and Group share: datasets, subgroups and attributes addressed by name relative to this
/// object. Names may be paths ("frames/3/position"); creating an object creates its missing parent groups.
class Location {
 public:
  std::int64_t id() const { return h_.id(); }
  const std::string& file_path() const { return file_; }
  /// This object's absolute path inside the file ("/" for the file itself).
  const std::string& object_path() const { return path_; }

  Group create_group(const std::string& name, const GroupOptions& options = {});
  /// A group linked nowhere yet: fill it, flush, then link() it, and a crash before the link cannot touch
  /// what the file already held.
  Group create_unlinked_group(const GroupOptions& options = {});
  /// Links `object` (from the same file) here under `name`.
  void link(const Location& object, const std::string& name);
  Group open_group(const std::string& name) const;
  /// Whether a link `name` exists (every component of a path is checked, so a missing parent is false).
  bool has(const std::string& name) const;
  bool has_attribute(const std::string& name) const;
  /// Names of the links in this group, in HDF5's name order ("10" sorts before "2").
  std::vector<std::string> children() const;

  Dataset open_dataset(const std::string& name) const;

  /// A new dataset of `shape` (row-major `values`, whose size must match); throws if `name` exists.
  template <Element T>
  void write(const std::string& name, std::span<const T> values, const Shape& shape);
  /// 1-D (any allocator: device-resident columns write their host copy).
  template <Element T, class A>
  void write(const std::string& name, const std::vector<T, A>& values) {
    write(name, std::span<const T>(values.data(), values.size()), Shape{values.size()});
  }
  /// 2-D, rows x cols, row-major.
  template <Element T, class A>
  void write(const std::string& name, const std::vector<T, A>& values, std::size_t rows, std::size_t cols) {
    write(name, std::span<const T>(values.data(), values.size()), Shape{rows, cols});
  }
  /// A scalar (rank-0) dataset.
  template <Element T>
  void write_scalar(const std::string& name, T value) {
    write(name, std::span<const T>(&value, 1), Shape{});
  }

  /// This process's rows of a new dataset of `shape` (shape[0] rows, each of the product of the other
  /// dimensions): `values` holds rows.size() of them, row-major, for the rows `rows` (strictly increasing).
  /// In a file of all ranks every rank calls it (collective) with the same name and shape, and the ranks'
  /// rows together must be every row once; elsewhere `rows` must be every row. std::logic_error if they
  /// are not (the count is checked, on every rank alike), std::invalid_argument for sizes that do not fit.
  template <Element T>
  void write_rows(const std::string& name, std::span<const T> values, std::span<const std::int64_t> rows,
                  const Shape& shape) {
    write_rows(name, values, RowSelection(rows, shape));
  }
  /// The same with the rows selected beforehand (several datasets of one shape and the same rows).
  template <Element T>
  void write_rows(const std::string& name, std::span<const T> values, const RowSelection& rows);

  template <Element T>
  Array<T> read(const std::string& name) const {
    return open_dataset(name).read<T>();
  }
  /// A dataset holding exactly one value (rank 0, or any shape of one element).
  template <Element T>
  T read_scalar(const std::string& name) const;

  /// Text of any length as a scalar fixed-length string dataset (attributes are limited to 64 KiB).
  void write_string(const std::string& name, const std::string& text);
  std::string read_string(const std::string& name) const;
  /// A 1-D dataset of fixed-length strings (e.g. group names).
  void write_strings(const std::string& name, const std::vector<std::string>& texts);
  std::vector<std::string> read_strings(const std::string& name) const;

  /// Attributes on this object; setting one that exists replaces it.
  template <Element T>
  void set_attribute(const std::string& name, T value) {
    set_attribute_array(name, std::span<const T>(&value, 1), Shape{});
  }
  template <Element T>
  void set_attribute(const std::string& name, const std::vector<T>& values) {
    set_attribute_array(name, std::span<const T>(values), Shape{values.size()});
  }
  void set_string_attribute(const std::string& name, const std::string& text);

  template <Element T>
  T attribute(const std::string& name) const;
  template <Element T>
  std::vector<T> attribute_array(const std::string& name) const;
  std::string string_attribute(const std::string& name) const;

 protected:
  Location(Handle h, std::string file, std::string path, bool all_ranks)
      : h_(std::move(h)), file_(std::move(file)), path_(std::move(path)), all_ranks_(all_ranks) {}
  /// A dataset's creation properties: in a file of all ranks its space is allocated at creation (HDF5's
  /// rule there) and never filled, since every value is written.
  Handle dataset_creation() const;
  /// Whether this process writes the values of a whole-dataset write (rank 0 in a file of all ranks).
  bool writes_whole() const;
  /// Absolute path of `name` below this object, for messages and for Dataset.
  std::string child_path(const std::string& name) const;

  Handle h_;
  std::string file_, path_;
  bool all_ranks_ = false;  // a file of every rank of the run (MPI-IO), not only in name

 private:
  template <Element T>
  void set_attribute_array(const std::string& name, std::span<const T> values, const Shape& shape);
};

class Group : public Location {
  friend class Location;
  using Location::Location;
};

struct FileOptions {
  /// false skips HDF5's flock(), so a reader holding the file open (h5py, a viewer) cannot make a long
  /// run fail when it reopens its output; the writer then owns consistency.
  bool file_locking = true;
  /// At creation: members per group index leaf is twice this (HDF5's sym_k "lk"; 0 keeps its 4). Larger
  /// leaves split less often as a group grows to thousands of members.
  unsigned group_leaf_k = 0;
  /// Every rank of an MPI run opens the file together (see the top of this header). Nothing changes in a
  /// serial build or a run of one rank.
  bool all_ranks = false;
  /// A process killed at any moment while it writes leaves a file HDF5 still opens (the writer's own
  /// commit order decides what it then holds). HDF5 (1.10, seen with strace) refuses a file shorter
  /// than the end of file its superblock records ("truncated file"), and a close made one: it gives back
  /// the unused tails of its metadata and small-data aggregation blocks, truncates the file to the lower
  /// end, and only then rewrites the superblock that still holds the last flush's larger one. So such a
  /// file aggregates nothing (H5Pset_meta_block_size and H5Pset_small_data_block_size 0). A flush that
  /// extends the file writes its superblock after the extension, so growth needs nothing. For outputs
  /// appended to in place, such as trajectories.
  bool survives_kill = false;
};

class File : public Location {
 public:
  enum class Mode { create, read_write, read_only };  // create truncates an existing file
  File(const std::string& path, Mode mode, FileOptions options = {});
  File(File&&) = default;
  File& operator=(File&&) = default;
  ~File() = default;  // closes without checking; call close() where the file must really be shut

  /// Writes every cached change to the file (H5Fflush).
  void flush();
  /// Whether every rank of an MPI run holds this file open together (all_ranks on more than one rank).
  bool on_all_ranks() const { return all_ranks_; }
  /// Closes the file and checks it really closed: std::logic_error if a group, dataset or attribute
  /// opened from it is still alive (HDF5 would keep the file open until that object goes).
  void close();
};

}  // namespace debris::h5
