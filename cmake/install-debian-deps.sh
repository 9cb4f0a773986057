#!/usr/bin/env bash
# Installs the Debian 12 packages debris builds with (nothing is downloaded at configure time).
#   --tests  also what the whole test suite needs: ParaView's pvpython (python3-paraview, about 1.2 GB
#            installed), which opens the HDF5/XDMF trajectory in the ParaViewOpensTrajectory test.
#   --mpi    also Open MPI and the parallel HDF5 (the DEBRIS_MPI=ON configuration, build-mpi). The serial
#            libhdf5-dev stays, and the serial build keeps finding it (through h5cc).
#   --hostdevice  also clang 19 with OpenMP offload to the host CPU as a separate device (the
#            DEBRIS_OFFLOAD=hostdevice configuration; about 30 s). libomp-19-dev replaces libomp-14-dev and
#            libomp-dev (clang 14's OpenMP runtime); the host build uses GCC's libgomp and is not affected.
# Skips apt entirely when everything is already there; uses sudo only when not root.
set -euo pipefail
with_tests=0
with_hostdevice=0
with_mpi=0
for arg in "$@"; do
  case "$arg" in
    --tests) with_tests=1 ;;
    --hostdevice) with_hostdevice=1 ;;
    --mpi) with_mpi=1 ;;
    *) echo "install-debian-deps.sh: unknown option '$arg' (valid: --tests, --hostdevice, --mpi)" >&2; exit 2 ;;
  esac
done
packages=(
  g++ cmake make
  libeigen3-dev libhdf5-dev libyaml-cpp-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libfftw3-dev           # FFTW 3: the rough surfaces' generator and spectra (core/rough)
  gcc-12-offload-nvptx   # the DEBRIS_OFFLOAD=nvptx configuration (GCC 12 OpenMP offload to NVIDIA GPUs)
  python3                # bench/perf_check.py
  libgmsh-dev            # Gmsh's C++ API: PeriDEM grain and wall shapes meshed in-process (scenarios/common/peridem/shape_mesh; the tests need it)
  gmsh                   # the Gmsh executable: scenarios/peridem/timing_study.py remeshes the deck's .geo files with -clscale
  gnuplot-nox            # the PNG plots of the patch-test and amorphous scenarios (skipped, with a note, without it)
  python3-matplotlib     # the sheared-junction pictures (scenarios/wear/plot.py)
  python3-numpy python3-h5py  # scenarios/peridem/compression.py, damage_picture.py, settled_pack.py (and their test)
  pybind11-dev python3-dev    # the Python module (`import debris`, scenarios/python)
  python3-pytest              # its tests (tests/python; configuring the tests needs it, as it needs Gmsh)
)
[ "$with_tests" -eq 0 ] || packages+=(python3-paraview)
[ "$with_mpi" -eq 0 ] || packages+=(libopenmpi-dev openmpi-bin libhdf5-openmpi-dev hdf5-tools)  # h5diff: tests/mpi
# clang-offload-packager comes from clang-tools-19; libomptarget and its x86_64 plugin from libomp-19-dev.
[ "$with_hostdevice" -eq 0 ] || packages+=(clang-19 clang-tools-19 libomp-19-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "debris: all Debian packages present"
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "debris: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
