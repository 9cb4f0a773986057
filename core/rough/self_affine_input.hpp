#pragma once
// A self-affine surface's parameters from an input section, and their descriptions for the key reference, so
// any executable that makes rough surfaces reads and documents the same keys:
//   {hurst: 0.8, rms_height: 2 nm, rolloff_wavelength: 40 nm, cutoff_wavelength: 2 nm, seed: 7}
// The checks that need no grid are made here, as InputErrors naming the key; the grid's (a spacing above
// half the cut-off wavelength) is generate_self_affine's, once the grid is known.
#include <string>

#include "core/rough/self_affine_surface.hpp"

namespace debris {

class InputNode;
class KeyReference;

/// The spec under `node` (a map), lengths in SI. InputError naming the key path and value for: hurst outside
/// (0, 1); both or neither of rms_height and rms_slope, or one not > 0; a wavelength not > 0 (the optional
/// ones: not >= 0); a cut-off not shorter than the roll-off, a largest wavelength shorter than the roll-off;
/// a negative seed.
SelfAffineSpec read_self_affine_spec(const InputNode& node);

/// Describes the keys read_self_affine_spec reads as the shared table `table` of `ref` (the section holding
/// them says `.follows(table)`).
void document_self_affine(KeyReference& ref, const std::string& table);

}  // namespace debris
