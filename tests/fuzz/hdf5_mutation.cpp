// Structure-aware mutation of an HDF5 checkpoint for the checkpoint targets (tests/fuzz/targets.cpp). A
// checkpoint mutated byte by byte mostly tests the HDF5 library's own parser (not ours to fix); what the
// restart loaders must survive is a well-formed file whose contents are wrong: a dataset missing, of another
// length, rank or type, holding NaN, a negative index or a count past the end. The fuzz input is read as a
// program of such edits, applied to a copy of a real checkpoint; the fuzzer mutates the program. The edited
// file is sealed again (core/io/hdf5_seal.hpp), or not, so that the edits reach the loaders' checks
// instead of stopping at the checksums.
#include "tests/fuzz/hdf5_mutation.hpp"

#include "core/io/hdf5_seal.hpp"

#include <hdf5.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace debris::fuzz {

namespace {

struct Object {
  std::string path;       // dataset path, or the path of the object an attribute is on
  std::string attribute;  // empty: a dataset
};

herr_t visit(hid_t, const char* name, const H5O_info_t* info, void* data) {
  auto* out = static_cast<std::vector<Object>*>(data);
  const std::string path = std::string("/") + (std::string(name) == "." ? "" : name);
  if (info->type == H5O_TYPE_DATASET) out->push_back({path, ""});
  return 0;
}

herr_t visit_attribute(hid_t, const char* name, const H5A_info_t*, void* data) {
  auto* out = static_cast<std::pair<std::string, std::vector<Object>*>*>(data);
  out->second->push_back({out->first, name});
  return 0;
}

herr_t visit_object(hid_t file, const char* name, const H5O_info_t* info, void* data) {
  auto* out = static_cast<std::vector<Object>*>(data);
  const std::string path = std::string(name) == "." ? "/" : std::string("/") + name;
  std::pair<std::string, std::vector<Object>*> ctx{path, out};
  if (info->num_attrs > 0) {
    hsize_t idx = 0;
    H5Aiterate_by_name(file, path.c_str(), H5_INDEX_NAME, H5_ITER_INC, &idx, visit_attribute, &ctx, H5P_DEFAULT);
  }
  return 0;
}

/// Reads the bytes of a program one at a time; zeros past its end.
class Program {
 public:
  explicit Program(const std::string& p) : p_(p) {}
  bool done() const { return at_ >= p_.size(); }
  unsigned byte() { return at_ < p_.size() ? static_cast<unsigned char>(p_[at_++]) : 0u; }
  unsigned word() { return byte() | (byte() << 8); }

 private:
  const std::string& p_;
  std::size_t at_ = 0;
};

/// A dataset's or attribute's values, as doubles and as 64-bit integers (whichever its class is), its
/// dimensions and its file type.
struct Values {
  H5T_class_t cls = H5T_NO_CLASS;
  std::vector<hsize_t> dims;
  std::vector<double> f;
  std::vector<long long> i;
  std::vector<std::string> s;
  std::size_t count() const { return cls == H5T_FLOAT ? f.size() : cls == H5T_INTEGER ? i.size() : s.size(); }
};

hsize_t elements(const std::vector<hsize_t>& dims) {
  hsize_t n = 1;
  for (hsize_t d : dims) n *= d;
  return n;
}

bool read_values(hid_t obj, bool attribute, Values& v) {
  const hid_t type = attribute ? H5Aget_type(obj) : H5Dget_type(obj);
  const hid_t space = attribute ? H5Aget_space(obj) : H5Dget_space(obj);
  bool ok = type >= 0 && space >= 0;
  if (ok) {
    v.cls = H5Tget_class(type);
    const int rank = H5Sget_simple_extent_ndims(space);
    v.dims.assign(static_cast<std::size_t>(std::max(rank, 0)), 0);
    if (rank > 0) H5Sget_simple_extent_dims(space, v.dims.data(), nullptr);
    const hsize_t n = elements(v.dims);
    if (n > (1u << 24)) ok = false;
    else if (v.cls == H5T_FLOAT) {
      v.f.resize(n);
      ok = (attribute ? H5Aread(obj, H5T_NATIVE_DOUBLE, v.f.data())
                      : H5Dread(obj, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.f.data())) >= 0;
    } else if (v.cls == H5T_INTEGER) {
      v.i.resize(n);
      ok = (attribute ? H5Aread(obj, H5T_NATIVE_LLONG, v.i.data())
                      : H5Dread(obj, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.i.data())) >= 0;
    } else if (v.cls == H5T_STRING && !H5Tis_variable_str(type)) {
      const std::size_t len = H5Tget_size(type);
      std::vector<char> buf(len * n);
      ok = (attribute ? H5Aread(obj, type, buf.data())
                      : H5Dread(obj, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data())) >= 0;
      for (hsize_t k = 0; ok && k < n; ++k) {
        std::string t(buf.data() + k * len, len);
        t.resize(t.find('\0') == std::string::npos ? t.size() : t.find('\0'));
        v.s.push_back(t);
      }
    } else {
      ok = false;
    }
  }
  if (type >= 0) H5Tclose(type);
  if (space >= 0) H5Sclose(space);
  return ok;
}

/// Writes `v` as a new dataset or attribute `name` on `loc` (which must not have it).
void write_values(hid_t loc, const Object& o, const Values& v) {
  const hsize_t n = v.count();
  std::vector<hsize_t> dims = v.dims;
  if (elements(dims) != n) dims = {n};
  const hid_t space = dims.empty() ? H5Screate(H5S_SCALAR) : H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  hid_t type = -1;
  std::vector<char> strings;
  const void* data = nullptr;
  if (v.cls == H5T_FLOAT) {
    type = H5Tcopy(H5T_NATIVE_DOUBLE);
    data = v.f.data();
  } else if (v.cls == H5T_INTEGER) {
    type = H5Tcopy(H5T_NATIVE_LLONG);
    data = v.i.data();
  } else {
    std::size_t len = 1;
    for (const std::string& t : v.s) len = std::max(len, t.size() + 1);
    type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, len);
    strings.assign(len * n, '\0');
    for (std::size_t k = 0; k < v.s.size(); ++k) std::copy(v.s[k].begin(), v.s[k].end(), strings.begin() + static_cast<long>(k * len));
    data = strings.data();
  }
  if (o.attribute.empty()) {
    const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
    H5Pset_create_intermediate_group(lcpl, 1);
    const hid_t d = H5Dcreate2(loc, o.path.c_str(), type, space, lcpl, H5P_DEFAULT, H5P_DEFAULT);
    if (d >= 0) {
      if (n > 0) H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
      H5Dclose(d);
    }
    H5Pclose(lcpl);
  } else {
    const hid_t a = H5Acreate_by_name(loc, o.path.c_str(), o.attribute.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (a >= 0) {
      if (n > 0) H5Awrite(a, type, data);
      H5Aclose(a);
    }
  }
  H5Tclose(type);
  H5Sclose(space);
}

const double kDoubles[] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity(), 0.0, -0.0, -1.0, 1.0, 1e308, -1e308, 1e-308,
                           4.9e-324, 1e9, 0.5, 3.0, 2147483648.0, -2147483649.0};
const long long kIntegers[] = {0, 1, -1, 2, 3, 4, 7, 8, 255, 65536, 2147483647LL, -2147483648LL, 2147483648LL,
                               4294967296LL, std::numeric_limits<long long>::max(), std::numeric_limits<long long>::min()};

void edit(hid_t file, const Object& o, Program& prog) {
  const bool exists = o.attribute.empty() ? H5Lexists(file, o.path.c_str(), H5P_DEFAULT) > 0 &&
                                                H5Oexists_by_name(file, o.path.c_str(), H5P_DEFAULT) > 0
                                          : H5Aexists_by_name(file, o.path.c_str(), o.attribute.c_str(), H5P_DEFAULT) > 0;
  const unsigned op = prog.byte() % 8;
  if (!exists) return;
  Values v;
  {
    const hid_t h = o.attribute.empty() ? H5Dopen2(file, o.path.c_str(), H5P_DEFAULT)
                                        : H5Aopen_by_name(file, o.path.c_str(), o.attribute.c_str(), H5P_DEFAULT, H5P_DEFAULT);
    if (h < 0) return;
    const bool ok = read_values(h, !o.attribute.empty(), v);
    o.attribute.empty() ? H5Dclose(h) : H5Aclose(h);
    if (!ok) return;
  }
  auto remove = [&] {
    if (o.attribute.empty()) H5Ldelete(file, o.path.c_str(), H5P_DEFAULT);
    else H5Adelete_by_name(file, o.path.c_str(), o.attribute.c_str(), H5P_DEFAULT);
  };
  const std::size_t n = v.count();
  switch (op) {
    case 0:  // delete it
      remove();
      return;
    case 1:
    case 2: {  // another length: 0, 1, n - 1, n + 1, 2n, or a small number
      const unsigned how = prog.byte() % 6;
      const std::size_t len = how == 0 ? 0 : how == 1 ? 1 : how == 2 ? (n ? n - 1 : 0) : how == 3 ? n + 1 : how == 4 ? 2 * n : prog.byte() % 16;
      v.dims = {len};
      if (v.cls == H5T_FLOAT) v.f.resize(len, v.f.empty() ? 1.0 : v.f.back());
      else if (v.cls == H5T_INTEGER) v.i.resize(len, v.i.empty() ? 1 : v.i.back());
      else v.s.resize(len, v.s.empty() ? std::string("x") : v.s.back());
      break;
    }
    case 3:
    case 4:
    case 5: {  // one element (or all) set to an awkward value
      if (n == 0) return;
      const unsigned which = prog.word();
      const bool all = which % 7 == 0;
      const std::size_t k = which % n;
      const unsigned pick = prog.byte();
      if (v.cls == H5T_FLOAT) {
        const double x = kDoubles[pick % std::size(kDoubles)];
        if (all) v.f.assign(n, x); else v.f[k] = x;
      } else if (v.cls == H5T_INTEGER) {
        // Beside the fixed values, indices just past the ends of the other arrays: the count itself and
        // one more, and a value from elsewhere in the same array shifted by one.
        // (Shifted with unsigned wrap-around: the value may already be one of the extremes.)
        const auto other = static_cast<unsigned long long>(v.i[prog.word() % n]);
        const long long choices[] = {static_cast<long long>(n), static_cast<long long>(n) + 1,
                                     static_cast<long long>(other + 1), static_cast<long long>(other - 1),
                                     kIntegers[pick % std::size(kIntegers)]};
        const long long x = choices[(pick >> 4) % std::size(choices)];
        if (all) v.i.assign(n, x); else v.i[k] = x;
      } else {
        const std::string choices[] = {"", std::string(300, 'x'), "\x01", "wall0", "top", "%s%n"};
        v.s[k] = choices[pick % std::size(choices)];
      }
      break;
    }
    case 6: {  // another type: integers as doubles, doubles as integers, strings as numbers
      if (v.cls == H5T_FLOAT) {
        v.cls = H5T_INTEGER;
        for (double x : v.f) v.i.push_back(std::isfinite(x) && std::abs(x) < 9e18 ? static_cast<long long>(x) : 0);
      } else if (v.cls == H5T_INTEGER) {
        v.cls = H5T_FLOAT;
        for (long long x : v.i) v.f.push_back(static_cast<double>(x));
      } else {
        v.cls = H5T_INTEGER;
        v.i.assign(n, 0);
      }
      break;
    }
    default:  // another rank: a scalar of the first value, or rows of one
      if (prog.byte() % 2 == 0 && n > 0) {
        v.dims = {};
        v.f.resize(std::min<std::size_t>(v.f.size(), 1));
        v.i.resize(std::min<std::size_t>(v.i.size(), 1));
        v.s.resize(std::min<std::size_t>(v.s.size(), 1));
      } else {
        v.dims = {static_cast<hsize_t>(n), 1};
      }
  }
  remove();
  write_values(file, o, v);
}

}  // namespace

void strip_seal(const std::string& path) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  haddr_t eoa = 0;
  const bool ok = file >= 0 && H5Fget_eoa(file, &eoa) >= 0;
  if (file >= 0) H5Fclose(file);
  if (!ok) throw std::runtime_error("fuzz: cannot read the end of the HDF5 data of " + path);
  std::filesystem::resize_file(path, eoa);
}

void mutate_hdf5(const std::string& seed, const std::string& out, const std::string& program) {
  std::filesystem::copy_file(seed, out, std::filesystem::copy_options::overwrite_existing);
  H5E_auto2_t func = nullptr;
  void* client = nullptr;
  H5Eget_auto2(H5E_DEFAULT, &func, &client);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t file = H5Fopen(out.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (file < 0) {
    H5Eset_auto2(H5E_DEFAULT, func, client);
    throw std::runtime_error("fuzz: cannot open the seed checkpoint copy " + out);
  }
  std::vector<Object> objects;
  H5Ovisit2(file, H5_INDEX_NAME, H5_ITER_INC, visit, &objects, H5O_INFO_BASIC);
  H5Ovisit2(file, H5_INDEX_NAME, H5_ITER_INC, visit_object, &objects, H5O_INFO_NUM_ATTRS);
  Program prog(program);
  while (!prog.done() && !objects.empty()) edit(file, objects[prog.word() % objects.size()], prog);
  H5Fclose(file);
  H5Eset_auto2(H5E_DEFAULT, func, client);
  if (program.empty() || static_cast<unsigned char>(program[0]) % 2 == 0) h5::seal(out);
}

}  // namespace debris::fuzz
