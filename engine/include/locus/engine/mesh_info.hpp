// The mesh report of every front end: `locus info`, Session::info,
// locus_session_info (C) and Session.info() (Python, a dict with the CLI
// JSON's keys); the fields are the core's MeshInfo (locus/mesh_info.hpp). It
// never fails on a mesh the readers return: it is what a user runs to find
// out why another command refused a file. Thesis §2.1.
#pragma once
#include "locus/export.h"
#include "locus/mesh.hpp"
#include "locus/mesh_info.hpp"

LOCUS_API_BEGIN
namespace locus {

// The report of `mesh` (a triangle or polygon mesh with its faces as given). O(nv + nf).
LOCUS_API MeshInfo mesh_info(const Mesh& mesh);

}  // namespace locus
LOCUS_API_END
