#pragma once
// Gmsh's C++ API (Debian's libgmsh-dev), in-process: the only code that includes gmsh.h besides the shapes
// it meshes (shape_mesh.cpp). Gmsh is one global state, so one user at a time holds it, under a lock.
//
// MSH files are read by debris's own reader for the ASCII formats Gmsh writes by default (2.2 and 4.1,
// core/io/gmsh_msh), because Gmsh 4.8's reader cannot say what is wrong with a file: a malformed number
// is "Error loading 'f'" without the line, an element that names a missing node is dropped without a
// word (a hole in the grain), and a missing file gives an empty model and no error (measured with this
// API). Every other file Gmsh reads (binary MSH, MSH 4.0, 3 or 1, ...) goes to Gmsh itself.
#include <functional>
#include <string>

#include "core/io/gmsh_msh.hpp"

namespace debris {

/// Whether this build has Gmsh's API (libgmsh-dev was found when it was configured).
bool gmsh_api_available();

/// Why a shape cannot be meshed in a build without the API, and what to do (for an input error).
std::string gmsh_api_missing();

/// The version of Gmsh's API ("4.8.0"), or "none" without it.
std::string gmsh_version();

/// Runs `work` on a fresh, empty Gmsh model while holding Gmsh. Gmsh is initialised on first use without
/// the user's configuration files (gmshrc, gmsh-options), so a mesh does not depend on who makes it, and
/// with its terminal output off. An error Gmsh raises inside `work` becomes an InputError for `key` =
/// `value`, with Gmsh's last messages. Without the API: an InputError saying how to get it.
void with_gmsh(const std::string& key, const std::string& value, const std::function<void()>& work);

/// A mesh file: ASCII MSH 2.2 and 4.1 through read_gmsh_msh (errors name the line), any other format
/// through Gmsh (where the API is built in), turned into the same SimplexMesh: nodes in tag order, the
/// linear simplices of the mesh's dimension, other elements of that dimension an error.
SimplexMesh read_mesh_file(const std::string& path);

}  // namespace debris
