# OpenMP configuration for debris. Only core/exec.hpp turns these into pragmas.
#   none  : host threads, `omp parallel for`; no target construct is compiled (see
#           shared/notes/openmp-offload.md: GCC 12 host fallback starts a thread per target region).
#   nvptx : `omp target teams distribute parallel for` through GCC 12's nvptx offload compiler
#           (Debian gcc-12-offload-nvptx). Falls back to the host when no GPU is present.
#   hostdevice : the same target pragmas through clang 19, offloaded to the host CPU as a separate device
#           (libomptarget's x86_64 plugin: target regions run on copies of the data). A missing enter or
#           update gives a wrong answer here, where GCC's host fallback shares memory and hides it; every
#           kernel also asserts that the arrays it reads are on the device (exec.hpp, DEBRIS_RESIDENT).
#           Needs clang-19, clang-tools-19 and libomp-19-dev (cmake/install-debian-deps.sh --hostdevice) and
#           -DCMAKE_CXX_COMPILER=clang++-19 -DCMAKE_C_COMPILER=clang-19.
find_package(OpenMP REQUIRED COMPONENTS CXX)

add_library(debris_openmp INTERFACE)
target_link_libraries(debris_openmp INTERFACE OpenMP::OpenMP_CXX)
# Kernels are branch-free math on doubles; errno from sqrt/pow would block vectorisation.
target_compile_options(debris_openmp INTERFACE -fno-math-errno)

if(DEBRIS_OFFLOAD STREQUAL "nvptx")
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    message(FATAL_ERROR "DEBRIS_OFFLOAD=nvptx needs g++ with gcc-12-offload-nvptx")
  endif()
  set(_debris_offload_flags -fopenmp -foffload=nvptx-none
      "-foffload-options=nvptx-none=-misa=sm_80 -lm -latomic")
  target_compile_definitions(debris_openmp INTERFACE DEBRIS_OFFLOAD_NVPTX=1)
  target_compile_options(debris_openmp INTERFACE ${_debris_offload_flags})
  # GCC needs the offload flags on the link line too, or __offload_func_table stays undefined.
  target_link_options(debris_openmp INTERFACE ${_debris_offload_flags})
elseif(DEBRIS_OFFLOAD STREQUAL "hostdevice")
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang" OR CMAKE_CXX_COMPILER_VERSION VERSION_LESS 17)
    message(FATAL_ERROR "DEBRIS_OFFLOAD=hostdevice needs clang >= 17 with libomptarget (Debian clang-19, "
                        "clang-tools-19, libomp-19-dev): -DCMAKE_CXX_COMPILER=clang++-19 -DCMAKE_C_COMPILER=clang-19")
  endif()
  get_filename_component(_debris_clang_bin "${CMAKE_CXX_COMPILER}" REALPATH)
  get_filename_component(_debris_llvm_lib "${_debris_clang_bin}/../../lib" ABSOLUTE)
  set(_debris_offload_flags -fopenmp -fopenmp-targets=x86_64-unknown-linux-gnu)
  target_compile_definitions(debris_openmp INTERFACE DEBRIS_OFFLOAD_HOSTDEVICE=1)
  target_compile_options(debris_openmp INTERFACE ${_debris_offload_flags})
  # libomptarget and its x86_64 plugin live beside clang (Debian: /usr/lib/llvm-19/lib), not on the loader's path.
  target_link_options(debris_openmp INTERFACE ${_debris_offload_flags} "-Wl,-rpath,${_debris_llvm_lib}")
elseif(DEBRIS_OFFLOAD STREQUAL "none")
  # With gcc-12-offload-nvptx installed, plain -fopenmp tries to offload; a host build must say no.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(debris_openmp INTERFACE -foffload=disable)
    target_link_options(debris_openmp INTERFACE -foffload=disable)
  endif()
else()
  message(FATAL_ERROR "DEBRIS_OFFLOAD must be none, nvptx or hostdevice, not '${DEBRIS_OFFLOAD}'")
endif()
message(STATUS "debris: DEBRIS_OFFLOAD=${DEBRIS_OFFLOAD}")
