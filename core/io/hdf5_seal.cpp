#include "core/io/hdf5_seal.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace debris::h5 {

namespace {

constexpr char kMagic[8] = {'D', 'B', 'R', 'S', 'E', 'A', 'L', '1'};
constexpr std::size_t kFooterBytes = 48;  // hdf5 length, entries, table sum, whole sum, footer sum, magic
constexpr std::uint64_t kP1 = 0x9e3779b185ebca87ull, kP2 = 0xc2b2ae3d27d4eb4full, kP3 = 0x165667b19e3779f9ull;

std::uint64_t rotl(std::uint64_t v, int r) { return (v << r) | (v >> (64 - r)); }

std::uint64_t load64(const unsigned char* p) {
  std::uint64_t v = 0;
  for (int b = 7; b >= 0; --b) v = (v << 8) | p[b];  // little-endian on any machine
  return v;
}

void store64(unsigned char* p, std::uint64_t v) {
  for (int b = 0; b < 8; ++b) p[b] = static_cast<unsigned char>(v >> (8 * b));
}

/// One lane absorbs one word: a bijection of the lane for a fixed word, and of the word for a fixed lane.
std::uint64_t absorb(std::uint64_t lane, std::uint64_t word) { return rotl(lane + word * kP2, 31) * kP1; }

std::string errno_text() { return std::strerror(errno); }

/// A file descriptor closed on scope exit.
struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

void read_exactly(int fd, unsigned char* buf, std::size_t bytes, std::uint64_t offset, const std::string& path) {
  while (bytes > 0) {
    const ssize_t r = ::pread(fd, buf, bytes, static_cast<off_t>(offset));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0)
      throw std::runtime_error("cannot read '" + path + "': " + (r < 0 ? errno_text() : "it is shorter than expected"));
    buf += r;
    bytes -= static_cast<std::size_t>(r);
    offset += static_cast<std::uint64_t>(r);
  }
}

/// Checksum of bytes [offset, offset + length) of the file.
std::uint64_t checksum_range(int fd, std::uint64_t offset, std::uint64_t length, const std::string& path) {
  std::vector<unsigned char> buf(static_cast<std::size_t>(std::min<std::uint64_t>(length, std::uint64_t{1} << 20)));
  Checksum c;
  while (length > 0) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(length, buf.size()));
    read_exactly(fd, buf.data(), n, offset, path);
    c.update(buf.data(), n);
    offset += n;
    length -= n;
  }
  return c.finish();
}

std::uint64_t file_size(int fd, const std::string& path) {
  struct stat st {};
  if (::fstat(fd, &st) != 0) throw std::runtime_error("cannot inspect '" + path + "': " + errno_text());
  return static_cast<std::uint64_t>(st.st_size);
}

struct Entry {
  std::string name;
  std::uint64_t offset = 0, length = 0, sum = 0;
};

/// Every dataset of the file whose values are stored contiguously, with where they lie.
std::vector<Entry> contiguous_datasets(const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) throw std::runtime_error("cannot open '" + path + "' to seal it");
  struct Visit {
    hid_t file;
    std::vector<Entry> entries;
  } visit{f, {}};
  const herr_t r = H5Ovisit2(
      f, H5_INDEX_NAME, H5_ITER_INC,
      [](hid_t, const char* name, const H5O_info_t* info, void* data) -> herr_t {
        if (info->type != H5O_TYPE_DATASET) return 0;
        auto* v = static_cast<Visit*>(data);
        const hid_t d = H5Dopen2(v->file, name, H5P_DEFAULT);
        if (d < 0) return -1;
        const haddr_t offset = H5Dget_offset(d);
        const hsize_t length = H5Dget_storage_size(d);
        H5Dclose(d);
        if (offset != HADDR_UNDEF && length > 0) v->entries.push_back({std::string("/") + name, offset, length, 0});
        return 0;
      },
      &visit, H5O_INFO_BASIC);
  H5Fclose(f);
  if (r < 0) throw std::runtime_error("cannot list the datasets of '" + path + "' to seal it");
  return std::move(visit.entries);
}

}  // namespace

void Checksum::update(const void* data, std::size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  total_ += bytes;
  if (pending_bytes_ > 0) {
    const std::size_t take = std::min(bytes, sizeof pending_ - pending_bytes_);
    std::memcpy(pending_ + pending_bytes_, p, take);
    pending_bytes_ += take;
    p += take;
    bytes -= take;
    if (pending_bytes_ < sizeof pending_) return;
    for (int k = 0; k < 4; ++k) lane_[k] = absorb(lane_[k], load64(pending_ + 8 * k));
    pending_bytes_ = 0;
  }
  for (; bytes >= 32; p += 32, bytes -= 32)
    for (int k = 0; k < 4; ++k) lane_[k] = absorb(lane_[k], load64(p + 8 * k));
  std::memcpy(pending_, p, bytes);
  pending_bytes_ = bytes;
}

std::uint64_t Checksum::finish() const {
  std::uint64_t lane[4] = {lane_[0], lane_[1], lane_[2], lane_[3]};
  if (pending_bytes_ > 0) {  // the last words, zero-padded (the length below tells the padding apart)
    unsigned char last[32] = {};
    std::memcpy(last, pending_, pending_bytes_);
    for (int k = 0; k < 4; ++k) lane[k] = absorb(lane[k], load64(last + 8 * k));
  }
  std::uint64_t h = total_ * kP3;
  for (int k = 0; k < 4; ++k) h = rotl(h ^ absorb(0, lane[k]), 27) * kP1 + kP2;
  h ^= h >> 33;
  h *= kP2;
  h ^= h >> 29;
  h *= kP3;
  return h ^ (h >> 32);
}

void seal(const std::string& path) {
  std::vector<Entry> entries = contiguous_datasets(path);
  Fd f{::open(path.c_str(), O_RDWR)};
  if (f.fd < 0) throw std::runtime_error("cannot open '" + path + "' to seal it: " + errno_text());
  const std::uint64_t length = file_size(f.fd, path);
  std::vector<unsigned char> table;
  for (Entry& e : entries) {
    if (e.offset + e.length > length)
      throw std::runtime_error("'" + path + "': dataset " + e.name + " lies beyond its end");
    e.sum = checksum_range(f.fd, e.offset, e.length, path);
    unsigned char head[28];
    store64(head, e.offset);
    store64(head + 8, e.length);
    store64(head + 16, e.sum);
    const auto n = static_cast<std::uint32_t>(e.name.size());
    for (int b = 0; b < 4; ++b) head[24 + b] = static_cast<unsigned char>(n >> (8 * b));
    table.insert(table.end(), head, head + sizeof head);
    table.insert(table.end(), e.name.begin(), e.name.end());
  }
  Checksum table_sum;
  table_sum.update(table.data(), table.size());
  unsigned char footer[kFooterBytes];
  store64(footer, length);
  store64(footer + 8, entries.size());
  store64(footer + 16, table_sum.finish());
  store64(footer + 24, checksum_range(f.fd, 0, length, path));
  Checksum footer_sum;
  footer_sum.update(footer, 32);
  store64(footer + 32, footer_sum.finish());
  std::memcpy(footer + 40, kMagic, sizeof kMagic);
  table.insert(table.end(), footer, footer + kFooterBytes);
  std::size_t done = 0;
  while (done < table.size()) {
    const ssize_t w = ::pwrite(f.fd, table.data() + done, table.size() - done, static_cast<off_t>(length + done));
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) throw std::runtime_error("cannot write the checksums of '" + path + "': " + errno_text());
    done += static_cast<std::size_t>(w);
  }
  // On disk before the caller renames the file over the previous one, so a crash cannot leave a sealed
  // name on unwritten blocks.
  if (::fsync(f.fd) != 0) throw std::runtime_error("cannot sync '" + path + "' to disk: " + errno_text());
}

bool verify_seal(const std::string& path) {
  Fd f{::open(path.c_str(), O_RDONLY)};
  if (f.fd < 0) throw std::runtime_error("cannot open '" + path + "': " + errno_text());
  const std::uint64_t size = file_size(f.fd, path);
  if (size < kFooterBytes) return false;
  unsigned char footer[kFooterBytes];
  read_exactly(f.fd, footer, kFooterBytes, size - kFooterBytes, path);
  if (std::memcmp(footer + 40, kMagic, sizeof kMagic) != 0) return false;
  const std::string damaged = "'" + path + "' is damaged: ";
  Checksum footer_sum;
  footer_sum.update(footer, 32);
  if (footer_sum.finish() != load64(footer + 32))
    throw std::runtime_error(damaged + "its checksum trailer (the last 48 bytes) does not match its own checksum");
  const std::uint64_t length = load64(footer), count = load64(footer + 8);
  if (length > size - kFooterBytes)
    throw std::runtime_error(damaged + "its checksum trailer names a length beyond the end of the file");
  std::vector<unsigned char> table(static_cast<std::size_t>(size - kFooterBytes - length));
  read_exactly(f.fd, table.data(), table.size(), length, path);
  Checksum table_sum;
  table_sum.update(table.data(), table.size());
  if (table_sum.finish() != load64(footer + 16))
    throw std::runtime_error(damaged + "its table of dataset checksums does not match its checksum");
  std::vector<Entry> entries;
  for (std::size_t at = 0; entries.size() < count;) {
    if (at + 28 > table.size()) throw std::runtime_error(damaged + "its table of dataset checksums is cut short");
    Entry e;
    e.offset = load64(&table[at]);
    e.length = load64(&table[at + 8]);
    e.sum = load64(&table[at + 16]);
    std::uint32_t n = 0;
    for (int b = 3; b >= 0; --b) n = (n << 8) | table[at + 24 + static_cast<std::size_t>(b)];
    at += 28;
    if (n > table.size() - at || e.offset > length || e.length > length - e.offset)
      throw std::runtime_error(damaged + "its table of dataset checksums is inconsistent");
    e.name.assign(reinterpret_cast<const char*>(&table[at]), n);
    at += n;
    entries.push_back(std::move(e));
  }
  if (checksum_range(f.fd, 0, length, path) == load64(footer + 24)) return true;
  // Something changed: say where, by the datasets' own checksums.
  std::string changed;
  for (const Entry& e : entries)
    if (checksum_range(f.fd, e.offset, e.length, path) != e.sum)
      changed += (changed.empty() ? "" : ", ") + e.name + " (bytes " + std::to_string(e.offset) + "-" +
                 std::to_string(e.offset + e.length - 1) + ")";
  if (!changed.empty())
    throw std::runtime_error(damaged + "the values of dataset " + changed +
                             " do not match the checksum written with them");
  throw std::runtime_error(damaged +
                           "its HDF5 structure (object headers, names, attributes: the bytes outside the datasets' "
                           "values) does not match the checksum written with it");
}

}  // namespace debris::h5
