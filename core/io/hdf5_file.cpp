#include "core/io/hdf5_file.hpp"

#include <hdf5.h>

#include "core/comm/communicator.hpp"
#include "core/comm/parallel_hdf5.hpp"

#include <algorithm>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <type_traits>

namespace debris::h5 {

static_assert(std::is_same_v<hid_t, std::int64_t> && std::is_same_v<herr_t, int>,
              "Handle stores hid_t as int64 and closers as int(int64): HDF5 >= 1.10 on this ABI");

namespace {

/// HDF5 prints its error stack to stderr by default; here failures become exceptions instead. In a
/// thread-safe libhdf5 (Debian's is) that setting is per thread, so every entry point calls this.
void quiet() {
  thread_local bool done = false;
  if (!done) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    done = true;
  }
}

/// The most specific description on HDF5's error stack (the innermost call), then clears the stack.
std::string reason() {
  std::string innermost;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_DOWNWARD,
      [](unsigned, const H5E_error2_t* e, void* data) -> herr_t {
        if (e->desc && *e->desc) *static_cast<std::string*>(data) = e->desc;
        return 0;
      },
      &innermost);
  H5Eclear2(H5E_DEFAULT);
  return innermost.empty() ? "no reason given by HDF5" : innermost;
}

[[noreturn]] void fail(const std::string& what, const std::string& object, const std::string& file) {
  throw std::runtime_error("HDF5: " + what + " '" + object + "' in file '" + file + "': " + reason());
}

template <Element T>
hid_t memory_type() {
  if constexpr (std::is_same_v<T, double>) return H5T_NATIVE_DOUBLE;
  else if constexpr (std::is_same_v<T, std::int32_t>) return H5T_NATIVE_INT32;
  else return H5T_NATIVE_INT64;
}

/// Little-endian standard types in the file, whatever machine wrote it.
template <Element T>
hid_t file_type() {
  if constexpr (std::is_same_v<T, double>) return H5T_IEEE_F64LE;
  else if constexpr (std::is_same_v<T, std::int32_t>) return H5T_STD_I32LE;
  else return H5T_STD_I64LE;
}

template <Element T>
const char* type_name() {
  if constexpr (std::is_same_v<T, double>) return "double";
  else if constexpr (std::is_same_v<T, std::int32_t>) return "int32";
  else return "int64";
}

std::string describe(hid_t type) {
  const std::string bytes = std::to_string(H5Tget_size(type)) + "-byte ";
  switch (H5Tget_class(type)) {
    case H5T_FLOAT: return bytes + "float";
    case H5T_INTEGER: return bytes + (H5Tget_sign(type) == H5T_SGN_NONE ? "unsigned integer" : "integer");
    case H5T_STRING: return "string";
    default: return "compound or other non-numeric type";
  }
}

/// Reading must not lose anything: same class, and no narrowing (an int64 dataset is not read as int32).
template <Element T>
void check_fits(hid_t stored, const std::string& object, const std::string& file) {
  const std::size_t size = H5Tget_size(stored);
  bool ok;
  if constexpr (std::is_same_v<T, double>) {
    ok = H5Tget_class(stored) == H5T_FLOAT && size <= sizeof(T);
  } else {
    ok = H5Tget_class(stored) == H5T_INTEGER &&
         (size < sizeof(T) || (size == sizeof(T) && H5Tget_sign(stored) == H5T_SGN_2));
  }
  if (!ok) {
    throw std::runtime_error("HDF5: '" + object + "' in file '" + file + "' is stored as " + describe(stored) +
                             ", which cannot be read as " + type_name<T>() + " without loss");
  }
}

std::size_t product(const Shape& shape) {
  std::size_t n = 1;
  for (std::size_t d : shape) n *= d;
  return n;
}

/// Link creation that makes missing parent groups, so "particles/x" needs no separate create_group.
Handle intermediate_lcpl() {
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  if (!lcpl.valid() || H5Pset_create_intermediate_group(lcpl.id(), 1) < 0) {
    throw std::runtime_error("HDF5: cannot make a link creation property list: " + reason());
  }
  return lcpl;
}

/// UTF-8, NUL-terminated, fixed length `chars` + 1.
Handle string_type(std::size_t chars) {
  Handle t(H5Tcopy(H5T_C_S1), H5Tclose);
  if (!t.valid() || H5Tset_size(t.id(), chars + 1) < 0 || H5Tset_strpad(t.id(), H5T_STR_NULLTERM) < 0 ||
      H5Tset_cset(t.id(), H5T_CSET_UTF8) < 0) {
    throw std::runtime_error("HDF5: cannot make a string type: " + reason());
  }
  return t;
}

/// Strings as fixed-length rows, padded with NULs.
std::vector<char> pack(const std::vector<std::string>& texts, std::size_t width) {
  std::vector<char> buf(texts.size() * width, '\0');
  for (std::size_t i = 0; i < texts.size(); ++i) std::memcpy(buf.data() + i * width, texts[i].data(), texts[i].size());
  return buf;
}

std::size_t longest(const std::vector<std::string>& texts) {
  std::size_t n = 0;
  for (const auto& t : texts) n = std::max(n, t.size());
  return n;
}

/// Strings of a dataset or attribute, fixed-length (ours) or variable-length (h5py's default).
/// `read(mem_type, buffer)` performs the H5Dread / H5Aread.
std::vector<std::string> read_texts(hid_t stored, hid_t space, const std::function<herr_t(hid_t, void*)>& read,
                                    const std::string& object, const std::string& file) {
  if (H5Tget_class(stored) != H5T_STRING) {
    throw std::runtime_error("HDF5: '" + object + "' in file '" + file + "' is stored as " + describe(stored) +
                             ", not as text");
  }
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  if (n < 0) fail("cannot size", object, file);
  std::vector<std::string> out(static_cast<std::size_t>(n));
  if (n == 0) return out;
  if (H5Tis_variable_str(stored) > 0) {
    Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
    if (!mem.valid() || H5Tset_size(mem.id(), H5T_VARIABLE) < 0) fail("cannot make a string type for", object, file);
    std::vector<char*> ptrs(out.size(), nullptr);
    if (read(mem.id(), ptrs.data()) < 0) fail("cannot read", object, file);
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = ptrs[i] ? ptrs[i] : "";
    H5Dvlen_reclaim(mem.id(), space, H5P_DEFAULT, ptrs.data());
  } else {
    const std::size_t width = H5Tget_size(stored);
    Handle mem(H5Tcopy(stored), H5Tclose);
    std::vector<char> buf(out.size() * width, '\0');
    if (!mem.valid() || read(mem.id(), buf.data()) < 0) fail("cannot read", object, file);
    for (std::size_t i = 0; i < out.size(); ++i) {
      const char* row = buf.data() + i * width;
      out[i].assign(row, strnlen(row, width));
    }
  }
  return out;
}

}  // namespace

// ---- Handle, Dataspace, Dataset ----

Handle& Handle::operator=(Handle&& o) noexcept {
  if (this != &o) {
    reset();
    id_ = o.id_;
    closer_ = o.closer_;
    o.id_ = -1;
  }
  return *this;
}

bool Handle::reset() noexcept {
  if (id_ < 0) return true;
  const bool ok = closer_(id_) >= 0;
  id_ = -1;
  return ok;
}

Dataspace Dataspace::scalar() {
  quiet();
  Handle h(H5Screate(H5S_SCALAR), H5Sclose);
  if (!h.valid()) throw std::runtime_error("HDF5: cannot make a scalar dataspace: " + reason());
  return Dataspace(std::move(h));
}

Dataspace Dataspace::simple(const Shape& shape) {
  quiet();
  std::vector<hsize_t> dims(shape.begin(), shape.end());
  Handle h(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
  if (!h.valid()) throw std::runtime_error("HDF5: cannot make a dataspace of rank " + std::to_string(dims.size()) + ": " + reason());
  return Dataspace(std::move(h));
}

Shape Dataspace::shape() const {
  const int rank = H5Sget_simple_extent_ndims(id());
  if (rank < 0) throw std::runtime_error("HDF5: cannot read a dataspace's rank: " + reason());
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  if (rank > 0 && H5Sget_simple_extent_dims(id(), dims.data(), nullptr) < 0) {
    throw std::runtime_error("HDF5: cannot read a dataspace's dimensions: " + reason());
  }
  return Shape(dims.begin(), dims.end());
}

std::size_t Dataspace::elements() const {
  const hssize_t n = H5Sget_simple_extent_npoints(id());
  if (n < 0) throw std::runtime_error("HDF5: cannot count a dataspace's elements: " + reason());
  return static_cast<std::size_t>(n);
}

Shape Dataset::shape() const {
  quiet();
  Handle space(H5Dget_space(id()), H5Sclose);
  if (!space.valid()) fail("cannot get the dataspace of", path_, file_);
  return Dataspace(std::move(space)).shape();
}

template <Element T>
Array<T> Dataset::read() const {
  quiet();
  Handle space_h(H5Dget_space(id()), H5Sclose);
  if (!space_h.valid()) fail("cannot get the dataspace of", path_, file_);
  const Dataspace space(std::move(space_h));
  Handle type(H5Dget_type(id()), H5Tclose);
  if (!type.valid()) fail("cannot get the type of", path_, file_);
  check_fits<T>(type.id(), path_, file_);
  Array<T> out;
  out.shape = space.shape();
  out.values.resize(space.elements());
  if (!out.values.empty() &&
      H5Dread(id(), memory_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, out.values.data()) < 0) {
    fail("cannot read", path_, file_);
  }
  return out;
}

// ---- Location ----

std::string Location::child_path(const std::string& name) const {
  if (!name.empty() && name.front() == '/') return name;
  return path_ == "/" ? "/" + name : path_ + "/" + name;
}

namespace {

Handle group_creation(const GroupOptions& options) {
  Handle gcpl(H5Pcreate(H5P_GROUP_CREATE), H5Pclose);
  if (!gcpl.valid()) return gcpl;
  // Tracking creation order is what makes HDF5 1.10 use the compact (1.8) layout in an old-format file.
  if ((options.reserved_name_bytes > 0 && H5Pset_local_heap_size_hint(gcpl.id(), options.reserved_name_bytes) < 0) ||
      (options.small && H5Pset_link_creation_order(gcpl.id(), H5P_CRT_ORDER_TRACKED) < 0)) {
    gcpl.reset();
  }
  return gcpl;
}

}  // namespace

Group Location::create_group(const std::string& name, const GroupOptions& options) {
  quiet();
  const Handle lcpl = intermediate_lcpl();
  const Handle gcpl = group_creation(options);
  if (!gcpl.valid()) fail("cannot set up group", child_path(name), file_);
  Handle g(H5Gcreate2(id(), name.c_str(), lcpl.id(), gcpl.id(), H5P_DEFAULT), H5Gclose);
  if (!g.valid()) fail("cannot create group", child_path(name), file_);
  return Group(std::move(g), file_, child_path(name), all_ranks_);
}

Group Location::create_unlinked_group(const GroupOptions& options) {
  quiet();
  const Handle gcpl = group_creation(options);
  if (!gcpl.valid()) fail("cannot set up an unlinked group in", path_, file_);
  Handle g(H5Gcreate_anon(id(), gcpl.id(), H5P_DEFAULT), H5Gclose);
  if (!g.valid()) fail("cannot create an unlinked group in", path_, file_);
  return Group(std::move(g), file_, "(unlinked group)", all_ranks_);
}

void Location::link(const Location& object, const std::string& name) {
  quiet();
  const Handle lcpl = intermediate_lcpl();
  if (H5Olink(object.id(), id(), name.c_str(), lcpl.id(), H5P_DEFAULT) < 0) fail("cannot link", child_path(name), file_);
}

Group Location::open_group(const std::string& name) const {
  quiet();
  Handle g(H5Gopen2(id(), name.c_str(), H5P_DEFAULT), H5Gclose);
  if (!g.valid()) fail("cannot open group", child_path(name), file_);
  return Group(std::move(g), file_, child_path(name), all_ranks_);
}

bool Location::has(const std::string& name) const {
  quiet();
  // H5Lexists fails (rather than saying no) when a parent is missing, so walk the path one link at a time.
  const bool absolute = !name.empty() && name.front() == '/';
  std::string prefix;
  bool any = false;
  for (std::size_t start = 0; start < name.size();) {
    const std::size_t end = std::min(name.find('/', start), name.size());
    if (end > start) {
      if (any || absolute) prefix += '/';
      prefix.append(name, start, end - start);
      any = true;
      const htri_t e = H5Lexists(id(), prefix.c_str(), H5P_DEFAULT);
      if (e < 0) fail("cannot look up", child_path(prefix), file_);
      if (e == 0) return false;
    }
    start = end + 1;
  }
  return any;
}

bool Location::has_attribute(const std::string& name) const {
  quiet();
  const htri_t e = H5Aexists(id(), name.c_str());
  if (e < 0) fail("cannot look up attribute '" + name + "' of", path_, file_);
  return e > 0;
}

std::vector<std::string> Location::children() const {
  quiet();
  std::vector<std::string> names;
  const herr_t r = H5Literate(
      id(), H5_INDEX_NAME, H5_ITER_INC, nullptr,
      [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
        static_cast<std::vector<std::string>*>(data)->emplace_back(name);
        return 0;
      },
      &names);
  if (r < 0) fail("cannot list the members of", path_, file_);
  return names;
}

Dataset Location::open_dataset(const std::string& name) const {
  quiet();
  Handle d(H5Dopen2(id(), name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d.valid()) fail("cannot open dataset", child_path(name), file_);
  return Dataset(std::move(d), file_, child_path(name));
}

template <Element T>
void Location::write(const std::string& name, std::span<const T> values, const Shape& shape) {
  quiet();
  const std::string object = child_path(name);
  if (product(shape) != values.size()) {
    throw std::invalid_argument("HDF5: writing '" + object + "' in file '" + file_ + "': " +
                                std::to_string(values.size()) + " values do not fill the shape given");
  }
  const Dataspace space = shape.empty() ? Dataspace::scalar() : Dataspace::simple(shape);
  const Handle lcpl = intermediate_lcpl(), dcpl = dataset_creation();
  Handle d(H5Dcreate2(id(), name.c_str(), file_type<T>(), space.id(), lcpl.id(), dcpl.id(), H5P_DEFAULT), H5Dclose);
  if (!d.valid()) fail("cannot create dataset", object, file_);
  if (writes_whole() && !values.empty() &&
      H5Dwrite(d.id(), memory_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0) {
    fail("cannot write dataset", object, file_);
  }
  if (!d.reset()) fail("cannot close dataset", object, file_);
}

Handle Location::dataset_creation() const {
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  if (!dcpl.valid() || (all_ranks_ && H5Pset_fill_time(dcpl.id(), H5D_FILL_TIME_NEVER) < 0))
    throw std::runtime_error("HDF5: cannot make a dataset creation property list: " + reason());
  return dcpl;
}

bool Location::writes_whole() const { return !all_ranks_ || comm::rank() == 0; }

RowSelection::RowSelection(std::span<const std::int64_t> rows, const Shape& shape)
    : shape_(shape), rows_(rows.size()), space_(Dataspace::simple(shape.empty() ? Shape{0} : shape)) {
  if (shape.empty()) throw std::invalid_argument("HDF5: selecting rows: a scalar has no rows");
  width_ = product(Shape(shape.begin() + 1, shape.end()));
  for (std::size_t k = 0; k < rows.size(); ++k)
    if (rows[k] < 0 || static_cast<std::size_t>(rows[k]) >= shape[0] || (k > 0 && rows[k] <= rows[k - 1]))
      throw std::invalid_argument("HDF5: selecting rows: row " + std::to_string(rows[k]) +
                                  " is out of order or beyond the " + std::to_string(shape[0]) + " rows");
  // The rows as blocks of consecutive rows, whole rows each; the values in memory follow in the same order.
  std::vector<hsize_t> start(shape.size(), 0), count(shape.size(), 1), block(shape.begin(), shape.end());
  if (H5Sselect_none(space_.id()) < 0) throw std::runtime_error("HDF5: cannot select rows: " + reason());
  for (std::size_t k = 0; k < rows.size();) {
    std::size_t end = k + 1;
    while (end < rows.size() && rows[end] == rows[end - 1] + 1) ++end;
    start[0] = static_cast<hsize_t>(rows[k]);
    block[0] = static_cast<hsize_t>(end - k);
    if (H5Sselect_hyperslab(space_.id(), H5S_SELECT_OR, start.data(), nullptr, count.data(), block.data()) < 0)
      throw std::runtime_error("HDF5: cannot select rows: " + reason());
    k = end;
  }
}

template <Element T>
void Location::write_rows(const std::string& name, std::span<const T> values, const RowSelection& rows) {
  quiet();
  const std::string object = child_path(name);
  const Shape& shape = rows.shape();
  if (values.size() != rows.rows() * rows.row_width()) {
    throw std::invalid_argument("HDF5: writing rows of '" + object + "' in file '" + file_ + "': " +
                                std::to_string(values.size()) + " values are not " + std::to_string(rows.rows()) +
                                " rows of " + std::to_string(rows.row_width()));
  }
  // Every row once: a row left out would hold whatever the disk held (no fill value is written).
  std::int64_t covered = static_cast<std::int64_t>(rows.rows());
  if (all_ranks_) comm::allreduce_sum(&covered, 1);
  if (covered != static_cast<std::int64_t>(shape[0]))
    throw std::logic_error("HDF5: writing rows of '" + object + "' in file '" + file_ + "': " +
                           std::to_string(covered) + " rows given for " + std::to_string(shape[0]));

  const Dataspace space = Dataspace::simple(shape);
  const Handle lcpl = intermediate_lcpl(), dcpl = dataset_creation();
  Handle d(H5Dcreate2(id(), name.c_str(), file_type<T>(), space.id(), lcpl.id(), dcpl.id(), H5P_DEFAULT), H5Dclose);
  if (!d.valid()) fail("cannot create dataset", object, file_);
  const Dataspace memory = Dataspace::simple({std::max<std::size_t>(values.size(), 1)});
  if (values.empty() && H5Sselect_none(memory.id()) < 0) fail("cannot select rows of", object, file_);
  Handle dxpl(H5Pcreate(H5P_DATASET_XFER), H5Pclose);
  if (!dxpl.valid()) fail("cannot make a transfer property list for", object, file_);
  const bool together = all_ranks_ && comm::hdf5_collective_transfer(dxpl.id());
  // Collective: every rank writes, those without rows too; alone, nothing to write is nothing to do.
  if ((together || !values.empty()) &&
      H5Dwrite(d.id(), memory_type<T>(), memory.id(), rows.id(), dxpl.id(), values.data()) < 0)
    fail("cannot write rows of", object, file_);
  if (!d.reset()) fail("cannot close dataset", object, file_);
}

template <Element T>
T Location::read_scalar(const std::string& name) const {
  const Array<T> a = read<T>(name);
  if (a.values.size() != 1) {
    throw std::runtime_error("HDF5: '" + child_path(name) + "' in file '" + file_ + "' holds " +
                             std::to_string(a.values.size()) + " values, not one");
  }
  return a.values[0];
}

void Location::write_string(const std::string& name, const std::string& text) {
  quiet();
  const std::string object = child_path(name);
  const Handle type = string_type(text.size());
  const Dataspace space = Dataspace::scalar();
  const Handle lcpl = intermediate_lcpl(), dcpl = dataset_creation();
  Handle d(H5Dcreate2(id(), name.c_str(), type.id(), space.id(), lcpl.id(), dcpl.id(), H5P_DEFAULT), H5Dclose);
  if (!d.valid()) fail("cannot create dataset", object, file_);
  const std::vector<char> buf = pack({text}, text.size() + 1);
  if (writes_whole() && H5Dwrite(d.id(), type.id(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data()) < 0) fail("cannot write dataset", object, file_);
  if (!d.reset()) fail("cannot close dataset", object, file_);
}

void Location::write_strings(const std::string& name, const std::vector<std::string>& texts) {
  quiet();
  const std::string object = child_path(name);
  const std::size_t width = longest(texts) + 1;
  const Handle type = string_type(width - 1);
  const Dataspace space = Dataspace::simple({texts.size()});
  const Handle lcpl = intermediate_lcpl(), dcpl = dataset_creation();
  Handle d(H5Dcreate2(id(), name.c_str(), type.id(), space.id(), lcpl.id(), dcpl.id(), H5P_DEFAULT), H5Dclose);
  if (!d.valid()) fail("cannot create dataset", object, file_);
  const std::vector<char> buf = pack(texts, width);
  if (writes_whole() && !texts.empty() && H5Dwrite(d.id(), type.id(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data()) < 0) {
    fail("cannot write dataset", object, file_);
  }
  if (!d.reset()) fail("cannot close dataset", object, file_);
}

std::vector<std::string> Location::read_strings(const std::string& name) const {
  const Dataset d = open_dataset(name);
  Handle space(H5Dget_space(d.id()), H5Sclose);
  Handle type(H5Dget_type(d.id()), H5Tclose);
  if (!space.valid() || !type.valid()) fail("cannot inspect", d.path(), file_);
  return read_texts(
      type.id(), space.id(),
      [&d](hid_t mem, void* buf) { return H5Dread(d.id(), mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf); }, d.path(), file_);
}

std::string Location::read_string(const std::string& name) const {
  const std::vector<std::string> texts = read_strings(name);
  if (texts.size() != 1) {
    throw std::runtime_error("HDF5: '" + child_path(name) + "' in file '" + file_ + "' holds " +
                             std::to_string(texts.size()) + " strings, not one");
  }
  return texts[0];
}

namespace {

/// Creates attribute `name` on `loc`, replacing one that exists.
Handle new_attribute(hid_t loc, const std::string& name, hid_t type, hid_t space, const std::string& object,
                     const std::string& file) {
  const htri_t exists = H5Aexists(loc, name.c_str());
  if (exists < 0 || (exists > 0 && H5Adelete(loc, name.c_str()) < 0)) {
    fail("cannot replace attribute '" + name + "' of", object, file);
  }
  Handle a(H5Acreate2(loc, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!a.valid()) fail("cannot create attribute '" + name + "' of", object, file);
  return a;
}

}  // namespace

template <Element T>
void Location::set_attribute_array(const std::string& name, std::span<const T> values, const Shape& shape) {
  quiet();
  const Dataspace space = shape.empty() ? Dataspace::scalar() : Dataspace::simple(shape);
  Handle a = new_attribute(id(), name, file_type<T>(), space.id(), path_, file_);
  if (!values.empty() && H5Awrite(a.id(), memory_type<T>(), values.data()) < 0) {
    fail("cannot write attribute '" + name + "' of", path_, file_);
  }
  if (!a.reset()) fail("cannot close attribute '" + name + "' of", path_, file_);
}

void Location::set_string_attribute(const std::string& name, const std::string& text) {
  quiet();
  const Handle type = string_type(text.size());
  const Dataspace space = Dataspace::scalar();
  Handle a = new_attribute(id(), name, type.id(), space.id(), path_, file_);
  const std::vector<char> buf = pack({text}, text.size() + 1);
  if (H5Awrite(a.id(), type.id(), buf.data()) < 0) fail("cannot write attribute '" + name + "' of", path_, file_);
  if (!a.reset()) fail("cannot close attribute '" + name + "' of", path_, file_);
}

template <Element T>
std::vector<T> Location::attribute_array(const std::string& name) const {
  quiet();
  const std::string object = "attribute '" + name + "' of " + path_;
  Handle a(H5Aopen(id(), name.c_str(), H5P_DEFAULT), H5Aclose);
  if (!a.valid()) fail("cannot open attribute '" + name + "' of", path_, file_);
  Handle space_h(H5Aget_space(a.id()), H5Sclose);
  Handle type(H5Aget_type(a.id()), H5Tclose);
  if (!space_h.valid() || !type.valid()) fail("cannot inspect attribute '" + name + "' of", path_, file_);
  check_fits<T>(type.id(), object, file_);
  std::vector<T> out(Dataspace(std::move(space_h)).elements());
  if (!out.empty() && H5Aread(a.id(), memory_type<T>(), out.data()) < 0) {
    fail("cannot read attribute '" + name + "' of", path_, file_);
  }
  return out;
}

template <Element T>
T Location::attribute(const std::string& name) const {
  const std::vector<T> v = attribute_array<T>(name);
  if (v.size() != 1) {
    throw std::runtime_error("HDF5: attribute '" + name + "' of '" + path_ + "' in file '" + file_ + "' holds " +
                             std::to_string(v.size()) + " values, not one");
  }
  return v[0];
}

std::string Location::string_attribute(const std::string& name) const {
  quiet();
  Handle a(H5Aopen(id(), name.c_str(), H5P_DEFAULT), H5Aclose);
  if (!a.valid()) fail("cannot open attribute '" + name + "' of", path_, file_);
  Handle space(H5Aget_space(a.id()), H5Sclose);
  Handle type(H5Aget_type(a.id()), H5Tclose);
  if (!space.valid() || !type.valid()) fail("cannot inspect attribute '" + name + "' of", path_, file_);
  const std::vector<std::string> texts = read_texts(
      type.id(), space.id(), [&a](hid_t mem, void* buf) { return H5Aread(a.id(), mem, buf); },
      "attribute '" + name + "' of " + path_, file_);
  if (texts.size() != 1) {
    throw std::runtime_error("HDF5: attribute '" + name + "' of '" + path_ + "' in file '" + file_ + "' holds " +
                             std::to_string(texts.size()) + " strings, not one");
  }
  return texts[0];
}

// ---- File ----

File::File(const std::string& path, Mode mode, FileOptions options) : Location(Handle(), path, "/", false) {
  quiet();
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose), fcpl(H5Pcreate(H5P_FILE_CREATE), H5Pclose);
  if (!fapl.valid() || !fcpl.valid() || (!options.file_locking && H5Pset_file_locking(fapl.id(), 0, 1) < 0) ||
      (options.group_leaf_k > 0 && H5Pset_sym_k(fcpl.id(), 0, options.group_leaf_k) < 0) ||
      (options.survives_kill &&
       (H5Pset_meta_block_size(fapl.id(), 0) < 0 || H5Pset_small_data_block_size(fapl.id(), 0) < 0))) {
    throw std::runtime_error("HDF5: cannot set up access to file '" + path + "': " + reason());
  }
  if (options.all_ranks) all_ranks_ = comm::hdf5_access_on_all_ranks(fapl.id());
  hid_t f = -1;
  switch (mode) {
    case Mode::create: f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl.id(), fapl.id()); break;
    case Mode::read_write: f = H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl.id()); break;
    case Mode::read_only: f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl.id()); break;
  }
  if (f < 0) {
    const char* how = mode == Mode::create ? "create" : mode == Mode::read_write ? "open for writing" : "open for reading";
    throw std::runtime_error(std::string("HDF5: cannot ") + how + " file '" + path + "': " + reason());
  }
  h_ = Handle(f, H5Fclose);
}

void File::flush() {
  quiet();
  if (H5Fflush(id(), H5F_SCOPE_LOCAL) < 0) throw std::runtime_error("HDF5: cannot flush file '" + file_ + "': " + reason());
}

void File::close() {
  quiet();
  if (!h_.valid()) return;
  const ssize_t open = H5Fget_obj_count(id(), H5F_OBJ_DATASET | H5F_OBJ_GROUP | H5F_OBJ_DATATYPE | H5F_OBJ_ATTR | H5F_OBJ_LOCAL);
  if (open != 0) {
    throw std::logic_error("HDF5: file '" + file_ + "' cannot be closed: " + std::to_string(open) +
                           " objects opened from it are still alive");
  }
  if (!h_.reset()) throw std::runtime_error("HDF5: cannot close file '" + file_ + "': " + reason());
}

// The element types of the header's Element concept.
#define DEBRIS_H5_INSTANTIATE(T)                                                                \
  template Array<T> Dataset::read<T>() const;                                                   \
  template void Location::write<T>(const std::string&, std::span<const T>, const Shape&);       \
  template void Location::write_rows<T>(const std::string&, std::span<const T>, const RowSelection&); \
  template T Location::read_scalar<T>(const std::string&) const;                                \
  template void Location::set_attribute_array<T>(const std::string&, std::span<const T>, const Shape&); \
  template std::vector<T> Location::attribute_array<T>(const std::string&) const;               \
  template T Location::attribute<T>(const std::string&) const;
DEBRIS_H5_INSTANTIATE(double)
DEBRIS_H5_INSTANTIATE(std::int32_t)
DEBRIS_H5_INSTANTIATE(std::int64_t)
#undef DEBRIS_H5_INSTANTIATE

}  // namespace debris::h5
