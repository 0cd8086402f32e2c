// Which Laplacian a mesh's queries run on, chosen once per mesh (Session, the
// CLI's --operator, the C API and Python, one name and one default everywhere):
//   * cotan  — the cotan Laplacian and lumped mass of the mesh's own triangles
//              (thesis §3.3, eqs. 3.5, 3.6); needs a manifold triangle mesh
//              without zero-area or needle faces or unreferenced vertices;
//   * robust — the Laplacian and mass of the intrinsic Delaunay triangulation of
//              the mesh's tufted cover with intrinsic mollification (Sharp & Crane,
//              SGP 2020; kernels/include/locus/kernels/mesh/robust_laplacian.hpp),
//              defined on every triangle soup; the heat method's gradient and
//              divergence run on its intrinsic triangles;
//   * auto   — (the default) cotan on a clean manifold mesh, results bit for bit
//              those of cotan; robust when the mesh has a non-manifold edge or
//              vertex, a zero-area or needle face, inconsistently oriented edges
//              or unreferenced vertices (kernels/.../mesh_defects.hpp).
// Unreferenced vertices get no value (NaN) from every query that answers per vertex.
#pragma once
#include <cstdint>
#include <string>

#include "locus/export.h"
#include "locus/mesh.hpp"

LOCUS_API_BEGIN
namespace locus {

enum class OperatorChoice { Auto, Cotan, Robust };

// "auto", "cotan", "robust".
const char* operator_choice_name(OperatorChoice c);
// The inverse; Error(BadUsage) naming the text and the choices otherwise.
OperatorChoice parse_operator_choice(const std::string& text);

// The defects that make `auto` choose the robust operator (counts, and the
// first offender of each kind, -1 when none; mesh_defects.hpp).
struct OperatorReport {
  OperatorChoice asked = OperatorChoice::Auto;
  bool robust = false;  // the operator used: robust, else cotan
  bool checked = false;  // the defects below were looked for (auto and robust on a triangle mesh)
  int64_t non_manifold_edges = 0, non_manifold_vertices = 0, zero_area_faces = 0, needle_faces = 0,
          inconsistent_orientation_edges = 0, unreferenced_vertices = 0;
  int64_t first_non_manifold_edge_v0 = -1, first_non_manifold_edge_v1 = -1, first_non_manifold_vertex = -1,
          first_zero_area_face = -1, first_needle_face = -1, first_unreferenced_vertex = -1;
  bool any_defect() const {
    return non_manifold_edges || non_manifold_vertices || zero_area_faces || needle_faces ||
           inconsistent_orientation_edges || unreferenced_vertices;
  }
  // "cotan" or "robust".
  const char* used() const { return robust ? "robust" : "cotan"; }
  // Why, in words: "3 non-manifold edges (first 12-40), 1 unreferenced vertex (first 7)",
  // "asked for", or "" on a clean mesh with auto.
  std::string reason() const;
};

// The choice for a triangle mesh with finite coordinates (Error(BadInput) for a
// non-triangle face or a non-finite coordinate when the defects must be looked
// for). Cotan: nothing is checked here (the queries refuse what they cannot
// take, as before). O(nv + nf).
OperatorReport choose_operator(const Mesh& triangles, OperatorChoice choice);

}  // namespace locus
LOCUS_API_END
