// Builds without pd_bond_passes_avx2.cpp (offload builds, CPUs other than x86-64: kernels/peridem/CMakeLists.txt)
// have no AVX2 sweeps: pd_bond_step runs the portable ones.
#include "kernels/peridem/pd_bond_rows.hpp"

namespace debris::pd_rows {

BondStepSweeps avx2_bond_step_sweeps() { return nullptr; }

}  // namespace debris::pd_rows
