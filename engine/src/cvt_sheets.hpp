// `cvt` on the manifold sheets of a mesh that is not a manifold
// (session_cvt_sheets.cpp). Internal to the engine.
#pragma once
#include "locus/engine/cvt_request.hpp"
#include "locus/engine/heat_time.hpp"
#include "locus/engine/operator_choice.hpp"
#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/mesh.hpp"
#include "locus/run_context.hpp"

namespace locus {

// The cvt command on a checked triangle mesh (`derived` its data,
// `components` its connected components): the sites raised to one per
// component, the cells' M - tL (robust or cotan) factored or loaded, run_cvt,
// the report with the request's own site count and the factor's timings.
// `lend`: the caller's derived data itself (non-null only when nobody else
// reads it meanwhile, SessionOptions::exclusive): its edge incidence is freed
// from the operator's assembly to the end of the first Lloyd run and rebuilt
// (incidence_loan.hpp). `lend_mesh`: `mesh` itself, on the same terms; its
// face_vertices are freed with the incidence (face_corner_loan.hpp).
CvtReport cvt_command_on(const Mesh& mesh, const MeshDerived& derived, int32_t components, bool robust,
                         const CvtRequest& req, const HeatTime& ts, const HeatTime& tc, const RunContext& ctx,
                         MeshDerived* lend = nullptr, Mesh* lend_mesh = nullptr);

// True when the Session's operator report names a defect the cells or the
// remesh cannot take (needles they can).
bool cvt_needs_sheets(const OperatorReport& op);

// The cvt command's call sequence on the sheets of `input` (triangles), the
// cells' operator robust or cotan, the labels and sites mapped back to `input`.
CvtReport cvt_on_sheets(const Mesh& input, bool robust, const CvtRequest& req, const HeatTime& ts,
                        const HeatTime& tc, const RunContext& ctx);

}  // namespace locus
