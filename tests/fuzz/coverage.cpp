// Edge coverage for the fuzzer (tests/fuzz/fuzz_main.cpp), from GCC's -fsanitize-coverage=trace-pc: the
// compiler calls __sanitizer_cov_trace_pc() at the start of every basic block of the instrumented files
// (the readers of outside data, cmake/DebrisFuzz.cmake). Each call counts the edge from the previous block
// into one byte of a 64 KiB map; the fuzzer clears the map before an input and keeps the input when the map
// shows an edge, or an edge count of another power-of-two class, never seen before. This file is compiled
// into debris_core only in fuzz builds (-DDEBRIS_FUZZ=ON) and is not itself instrumented.
#include <cstdint>

extern "C" {

std::uint8_t debris_fuzz_edges[1 << 16];

void __sanitizer_cov_trace_pc() {
  static thread_local std::uintptr_t previous = 0;
  const auto pc = reinterpret_cast<std::uintptr_t>(__builtin_return_address(0));
  const std::uintptr_t here = (pc >> 4) ^ (pc << 8);
  ++debris_fuzz_edges[(here ^ previous) & 0xffff];
  previous = here >> 1;
}

}  // extern "C"
