#pragma once
// What every executable's main does with what escapes its run, so that an exit status means one thing
// across debris_dem, debris_peridem, debris_patch, debris_amorphous and debris_restitution (core/error.hpp):
// 2 bad input, 3 the run could not finish, 1 a bug. Also the command line: a malformed one is bad input.
#include <CLI/CLI.hpp>
#include <exception>
#include <functional>
#include <iostream>
#include <new>
#include <string>

#include "core/comm/communicator.hpp"
#include "core/error.hpp"

namespace debris {

/// Parses the command line; --help and --version print and give 0, anything malformed prints CLI11's
/// message and gives kExitInput. Returns -1 when the run should go on.
inline int parse_command_line(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : kExitInput;
  }
  return -1;
}

/// Started by mpirun as N > 1 processes, a program that runs as one process would run the whole input N
/// times over and write the same files: exit 2 on every process before anything is written, the first
/// one saying why. `runs_on_ranks`: the program's model runs cut among ranks (debris_dem, debris_peridem),
/// which an MPI build allows. Returns -1 to go on. (Counted from the launcher's environment, so it holds
/// before MPI starts and in a serial build.)
inline int refuse_many_processes(const std::string& program, bool runs_on_ranks = false) {
  const int n = comm::launched_processes();
  if (n <= 1 || (comm::mpi_build() && runs_on_ranks)) return -1;
  if (comm::launched_rank() == 0) {
    std::cerr << program << ": input error: 'mpirun -np' = " << n << ": ";
    if (comm::mpi_build())
      std::cerr << program << " runs as one process (of debris's executables, debris_dem and debris_peridem "
                   "run on MPI ranks); run it without mpirun\n";
    else
      std::cerr << "this debris was built without MPI (DEBRIS_MPI=OFF), so each of the " << n
                << " processes would run the whole input and write the same files; run it as one process "
                   "(without mpirun)\n";
  }
  return kExitInput;
}

/// Runs `body` and turns an escaping exception into one line on stderr ("<program>: ...") and its status.
inline int exit_status_of(const std::string& program, const std::function<int()>& body) {
  try {
    return body();
  } catch (const InputError& e) {
    std::cerr << program << ": " << e.what() << std::endl;
    return kExitInput;
  } catch (const OutputError& e) {
    std::cerr << program << ": stopped: " << e.what() << std::endl;
    return kExitUnfinished;
  } catch (const RunStop& e) {
    std::cerr << program << ": stopped: " << e.what() << std::endl;
    return kExitUnfinished;
  } catch (const std::bad_alloc&) {
    std::cerr << program << ": stopped: out of memory" << std::endl;
    return kExitUnfinished;
  } catch (const std::exception& e) {
    std::cerr << program << ": error: " << e.what() << std::endl;
    return 1;
  }
}

}  // namespace debris
