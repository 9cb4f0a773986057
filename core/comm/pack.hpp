#pragma once
// Columns to bytes and back, for messages between ranks: the values of chosen rows of a column appended to
// a byte buffer, and read back in the same order. Raw bytes, so a ghost or a migrated particle keeps its
// owner's bits exactly.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <utility>
#include <vector>

namespace debris::comm {

/// Appends column[rows[k]] for every k.
template <class Column, class Index>
void pack_rows(const Column& column, const std::vector<Index>& rows, std::vector<char>& buffer) {
  using T = typename Column::value_type;
  const std::size_t at = buffer.size();
  buffer.resize(at + rows.size() * sizeof(T));
  char* out = buffer.data() + at;
  for (std::size_t k = 0; k < rows.size(); ++k, out += sizeof(T))
    std::memcpy(out, &column[static_cast<std::size_t>(rows[k])], sizeof(T));
}

/// Appends one value.
template <class T>
void pack_value(const T& v, std::vector<char>& buffer) {
  const std::size_t at = buffer.size();
  buffer.resize(at + sizeof(T));
  std::memcpy(buffer.data() + at, &v, sizeof(T));
}

/// The position column of `axis` (0, 1, 2: x, y, z) of a particle store (Particles).
template <class Store>
const double* position(const Store& p, int axis) {
  return axis == 0 ? p.x.data() : (axis == 1 ? p.y.data() : p.z.data());
}

/// Appends whole particle records (every column of a store with for_each_column: Particles): their count,
/// then column by column. What the halo sends at a rebuild and what migration sends; unpack_records reads it.
template <class Store, class Index>
void pack_records(const Store& p, const std::vector<Index>& rows, std::vector<char>& buffer) {
  pack_value(static_cast<std::int64_t>(rows.size()), buffer);
  p.for_each_column([&](const char*, const auto& col) { pack_rows(col, rows, buffer); });
}

/// Reads back what pack_* wrote, front to back.
class Unpacker {
 public:
  explicit Unpacker(const std::vector<char>& buffer) : buffer_(buffer) {}
  /// count values into column[first, first + count).
  template <class Column>
  void rows(Column& column, std::size_t first, std::size_t count) {
    using T = typename Column::value_type;
    need(count * sizeof(T));
    if (count) std::memcpy(&column[first], buffer_.data() + at_, count * sizeof(T));
    at_ += count * sizeof(T);
  }
  template <class T>
  T value() {
    T v;
    need(sizeof(T));
    std::memcpy(&v, buffer_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  bool done() const { return at_ == buffer_.size(); }
  /// Appends the records pack_records wrote to `p`; returns the index of the first and their count.
  template <class Store>
  std::pair<std::size_t, std::size_t> records(Store& p) {
    const auto n = static_cast<std::size_t>(value<std::int64_t>());
    const std::size_t first = p.size();
    p.resize(first + n);
    p.for_each_column([&](const char*, auto& col) { rows(col, first, n); });
    return {first, n};
  }

 private:
  void need(std::size_t n) const {
    if (at_ + n > buffer_.size()) throw std::logic_error("comm: a message shorter than its contents");
  }
  const std::vector<char>& buffer_;
  std::size_t at_ = 0;
};

}  // namespace debris::comm
