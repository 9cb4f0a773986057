// Every test of this binary, and every executable it starts, holds the input readers to their key
// references (core/io/key_reference.hpp): with DEBRIS_KEY_AUDIT=1 a key read without a description that
// matches it (kind, unit, default, choices) ends the read with an error, so an undocumented key fails the
// suite. Set before main() runs; an explicit DEBRIS_KEY_AUDIT=0 in the environment is kept.
#include <cstdlib>

namespace {
[[maybe_unused]] const int kKeyAuditOn = setenv("DEBRIS_KEY_AUDIT", "1", /*overwrite=*/0);
}  // namespace
