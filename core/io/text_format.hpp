#pragma once
// Numbers in text outputs (dump frames, LAMMPS data files, CSV): full double precision (%.17g, so a value
// read back is the same bits), and independent of the locale's decimal separator.
#include <charconv>
#include <string>

namespace debris {

inline void append_number(std::string& out, double v) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 17);
  out.append(buf, res.ptr);
}

template <class Int>
inline void append_number(std::string& out, Int v) {
  char buf[24];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, res.ptr);
}

}  // namespace debris
