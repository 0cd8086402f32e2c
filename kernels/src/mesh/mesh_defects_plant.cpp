// Planting mesh defects into a clean triangle mesh (mesh_defects_plant.hpp):
// the degenerate and non-manifold inputs of real assets (Sharp & Crane, SGP 2020,
// §6 tests the robust Laplacian on the same kinds), made reproducible. Works on a
// face list; each site looks its faces up in the current list (a few sites, a
// linear scan each).
#include "locus/kernels/mesh/mesh_defects_plant.hpp"

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

namespace locus {

namespace {

using Tri = std::array<int32_t, 3>;

struct Soup {
  std::vector<double> x, y, z;
  std::vector<Tri> faces;
  int32_t add(double px, double py, double pz) {
    x.push_back(px), y.push_back(py), z.push_back(pz);
    return static_cast<int32_t>(x.size()) - 1;
  }
  int32_t lerp(int32_t a, int32_t b, double t) {
    return add(x[a] + t * (x[b] - x[a]), y[a] + t * (y[b] - y[a]), z[a] + t * (z[b] - z[a]));
  }
};

int32_t corner_of(const Tri& f, int32_t v) { return f[0] == v ? 0 : f[1] == v ? 1 : f[2] == v ? 2 : -1; }

// The first face holding vertex v, or -1.
int32_t face_at(const Soup& s, int32_t v) {
  for (size_t f = 0; f < s.faces.size(); ++f)
    if (corner_of(s.faces[f], v) >= 0) return static_cast<int32_t>(f);
  return -1;
}

// The face other than f running b -> a, or -1.
int32_t across(const Soup& s, int32_t f, int32_t a, int32_t b) {
  for (size_t g = 0; g < s.faces.size(); ++g) {
    const int32_t k = corner_of(s.faces[g], b);
    if (static_cast<int32_t>(g) != f && k >= 0 && s.faces[g][(k + 1) % 3] == a) return static_cast<int32_t>(g);
  }
  return -1;
}

// Splits edge a -> b of face f (apex c) at parameter t; the face across (apex d)
// too when both_sides; otherwise the crack is closed by the flat triangle (p, a, b).
void split_edge(Soup& s, int32_t f, double t, bool both_sides) {
  const Tri F = s.faces[f];
  const int32_t a = F[0], b = F[1], c = F[2];
  const int32_t g = across(s, f, a, b);
  if (g < 0) return;
  const Tri G = s.faces[g];
  const int32_t d = G[(corner_of(G, a) + 1) % 3];
  const int32_t p = s.lerp(a, b, t);
  s.faces[f] = {a, p, c};
  s.faces.push_back({p, b, c});
  if (both_sides) {
    s.faces[g] = {b, p, d};
    s.faces.push_back({p, a, d});
  } else {
    s.faces.push_back({p, a, b});
  }
}

void plant_at(Soup& s, PlantedDefect kind, int32_t v, double h) {
  const int32_t f = face_at(s, v);
  if (f < 0) return;
  const Tri F = s.faces[f];
  const int32_t k = corner_of(F, v);
  const Tri R = {F[k], F[(k + 1) % 3], F[(k + 2) % 3]};  // starts at v
  switch (kind) {
    case PlantedDefect::Fin: {
      // Apex above the edge midpoint, along the midpoint's direction from the origin
      // (outward on a sphere about it), at height h.
      const double mx = 0.5 * (s.x[R[0]] + s.x[R[1]]), my = 0.5 * (s.y[R[0]] + s.y[R[1]]),
                   mz = 0.5 * (s.z[R[0]] + s.z[R[1]]);
      const double r = std::sqrt(mx * mx + my * my + mz * mz);
      const double u = r > 0 ? h / r : 0.0;
      s.faces.push_back({R[0], R[1], s.add(mx * (1 + u), my * (1 + u), mz * (1 + u) + (r > 0 ? 0.0 : h))});
      break;
    }
    case PlantedDefect::Bowtie: {
      std::vector<int32_t> fan;
      for (size_t g = 0; g < s.faces.size(); ++g)
        if (corner_of(s.faces[g], v) >= 0) fan.push_back(static_cast<int32_t>(g));
      // A fan face sharing no vertex but v with the first one.
      for (size_t q = 1; q < fan.size(); ++q) {
        int shared = 0;
        for (const int32_t w : s.faces[fan[q]]) shared += corner_of(s.faces[fan[0]], w) >= 0;
        if (shared == 1) {
          s.faces.erase(s.faces.begin() + fan[q]);
          s.faces.erase(s.faces.begin() + fan[0]);
          break;
        }
      }
      break;
    }
    case PlantedDefect::ZeroArea:
      s.faces[f] = R;
      split_edge(s, f, 0.5, false);
      break;
    case PlantedDefect::Needle:
      s.faces[f] = R;
      split_edge(s, f, 1e-6, true);
      break;
    case PlantedDefect::FlippedPatch:
      for (Tri& g : s.faces)
        if (corner_of(g, v) >= 0) std::swap(g[1], g[2]);
      break;
    case PlantedDefect::Unreferenced:
      s.add(s.x[v] * 2.0, s.y[v] * 2.0, s.z[v] * 2.0);
      break;
    case PlantedDefect::DuplicateFace:
      s.faces.push_back(F);
      break;
  }
}

}  // namespace

const char* planted_defect_name(PlantedDefect kind) {
  switch (kind) {
    case PlantedDefect::Fin: return "fin";
    case PlantedDefect::Bowtie: return "bowtie";
    case PlantedDefect::ZeroArea: return "zero_area";
    case PlantedDefect::Needle: return "needle";
    case PlantedDefect::FlippedPatch: return "flipped_patch";
    case PlantedDefect::Unreferenced: return "unreferenced";
    case PlantedDefect::DuplicateFace: return "duplicate_face";
  }
  return "?";
}

Mesh plant_mesh_defect(const Mesh& clean, PlantedDefect kind, int32_t count) {
  validate_mesh_arrays(clean);
  if (!clean.is_triangle_mesh()) fail(ErrorCode::BadInput, "plant_mesh_defect: needs a triangle mesh");
  const int32_t nv = clean.num_vertices();
  Soup s;
  s.x.assign(clean.x.begin(), clean.x.end());
  s.y.assign(clean.y.begin(), clean.y.end());
  s.z.assign(clean.z.begin(), clean.z.end());
  for (int32_t f = 0; f < clean.num_faces(); ++f) s.faces.push_back({clean.f0[f], clean.f1[f], clean.f2[f]});
  const double h = mean_edge_length(clean);
  for (int32_t q = 0; q < count && nv > 0; ++q) {
    // From the top of the id range down, evenly spaced.
    const int32_t v = nv - 1 - static_cast<int32_t>(static_cast<int64_t>(q) * nv / std::max(count, 1));
    plant_at(s, kind, v, h);
  }
  Mesh m;
  for (size_t v = 0; v < s.x.size(); ++v) m.add_vertex(s.x[v], s.y[v], s.z[v]);
  for (const Tri& f : s.faces) m.add_triangle(f[0], f[1], f[2]);
  return m;
}

}  // namespace locus
