#pragma once
// Tiling a relaxed periodic sample into a larger one (`particles.replicate` of a debris_dem input): a sample
// relaxed in a periodic box is, by construction, a periodic packing, so n_x x n_y x n_z copies side by side,
// each shifted by whole box lengths, continue it across every seam: each particle sees across a seam the
// neighbours it saw across the periodic face, at the same distances (tests/test_replicate_sample.cpp checks
// this pair by pair). What the tiling does not add is disorder on the larger scale: the tiled packing repeats
// with the original box's period, which a rough surface's longest wavelength should not resonate with.
#include <array>

namespace debris {

class Box;
class Particles;

/// Tiles `p` (every column; positions first folded into `box` along every axis, image counts reset) n[a]
/// times along each axis a; copy (cx, cy, cz) is shifted by (cx Lx, cy Ly, cz Lz) and its ids are
/// id + c (max_id + 1), c = cx + n_x (cy + n_y cz), so the original keeps its ids. `box` grows to match (its
/// periodicity kept). n = {1, 1, 1} changes nothing.
void replicate_sample(Particles& p, Box& box, std::array<int, 3> n);

}  // namespace debris
