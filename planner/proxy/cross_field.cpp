// The smoothest cross field (cross_field.hpp): Knöppel et al. 2013 on the
// triangles of the surface, one complex value per triangle.
#include "planner/proxy/cross_field.hpp"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

#include "planner/common/index.hpp"
#include "planner/mesh/soup.hpp"
#include "planner/proxy/remesh.hpp"

namespace planner {

namespace {

using Complex = std::complex<double>;
using ComplexVector = Eigen::VectorXcd;
using ComplexMatrix = Eigen::SparseMatrix<Complex>;

constexpr int kSymmetry = 4;  // a cross: four directions
const double kPi = std::acos(-1.0);

// The vector of half-edge h (from its start to its end).
Vec3 halfedge_vector(const HalfedgeMesh& mesh, int h) {
  return mesh.position(mesh.to(h)) - mesh.position(mesh.from(h));
}

// Each triangle's frame: x along its first side, y = n x x; its area.
struct Frames {
  std::vector<Vec3> x, y, normal;
  std::vector<double> area;
};

Frames triangle_frames(const HalfedgeMesh& mesh) {
  Frames frames;
  const std::size_t nf = at(mesh.num_faces());
  frames.x.resize(nf);
  frames.y.resize(nf);
  frames.normal.resize(nf);
  frames.area.resize(nf);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Vec3 n = mesh.face_normal(f);
    const int h = mesh.face_start(f);
    frames.area[at(f)] = 0.5 * n.norm();
    frames.x[at(f)] = halfedge_vector(mesh, h).normalized();
    // A triangle of nil area (a fan over a concave polygon can make one)
    // gets some frame: its weight in the energy is nil.
    frames.normal[at(f)] = n.norm() > 0.0 ? n.normalized() : frames.x[at(f)].unitOrthogonal();
    frames.y[at(f)] = frames.normal[at(f)].cross(frames.x[at(f)]);
  }
  return frames;
}

// The angle of vector v in the frame of triangle f.
double angle_in(const Frames& frames, int f, const Vec3& v) {
  return std::atan2(v.dot(frames.y[at(f)]), v.dot(frames.x[at(f)]));
}

// The Levi-Civita transport of the field's fourth power from face(h) to
// face(twin(h)): unfolding the two triangles about their shared edge keeps
// angles to the edge, so an angle φ of face(h) becomes φ + θ_g(e) − θ_f(e).
Complex transport(const HalfedgeMesh& mesh, const Frames& frames, int h) {
  const Vec3 e = halfedge_vector(mesh, h);
  const double rho =
      angle_in(frames, mesh.face(mesh.twin(h)), e) - angle_in(frames, mesh.face(h), e);
  return std::polar(1.0, kSymmetry * rho);
}

Vec3 centroid(const HalfedgeMesh& mesh, int f) {
  const int h = mesh.face_start(f);
  return (mesh.position(mesh.from(h)) + mesh.position(mesh.to(h)) +
          mesh.position(mesh.to(mesh.next(h)))) /
         3.0;
}

// The Hermitian energy matrix A of the discrete Dirichlet energy
//   E(u) = Σ_edges w_e |u_g − r_fg u_f|²
// of a field constant per triangle: w_e is the edge's length over the
// length of the dual edge between the two centroids (through the edge's
// midpoint, the hinge unfolded), the finite-volume weight of the gradient
// across the edge. Positive for every mesh, and without unit: scaling the
// surface scales A's eigenvalues against M's areas only.
ComplexMatrix energy_matrix(const HalfedgeMesh& mesh, const Frames& frames) {
  std::vector<Eigen::Triplet<Complex>> entries;
  entries.reserve(at(mesh.num_halfedges()) * 2);
  for (int h = 0; h < mesh.num_halfedges(); ++h) {
    const int t = mesh.twin(h);
    if (t < h) continue;  // each interior edge once; boundary edges have t < 0
    const int f = mesh.face(h);
    const int g = mesh.face(t);
    const Vec3 midpoint = 0.5 * (mesh.position(mesh.from(h)) + mesh.position(mesh.to(h)));
    const double dual =
        (centroid(mesh, f) - midpoint).norm() + (centroid(mesh, g) - midpoint).norm();
    const double w = mesh.edge_length(h) / dual;
    const Complex r = transport(mesh, frames, h);
    // u^H A u = Σ w (|u_f|² + |u_g|² − conj(u_g) r u_f − conj(u_f) conj(r) u_g)
    entries.emplace_back(f, f, w);
    entries.emplace_back(g, g, w);
    entries.emplace_back(g, f, -w * r);
    entries.emplace_back(f, g, -w * std::conj(r));
  }
  ComplexMatrix a(mesh.num_faces(), mesh.num_faces());
  a.setFromTriplets(entries.begin(), entries.end());
  return a;
}

// u^H A u / u^H M u.
double rayleigh_quotient(const ComplexMatrix& a, const Eigen::VectorXd& mass,
                         const ComplexVector& u) {
  const ComplexVector au = a * u;
  const double num = u.dot(au).real();  // dot conjugates its left side
  const double den = (u.array().abs2() * mass.array()).sum();
  return den > 0.0 ? num / den : 0.0;
}

// The eigenvector of the smallest eigenvalue of A u = λ M u: inverse power
// iteration, each step one solve with the factorisation of A + εM (ε a
// millionth of A's mean diagonal over M's, far below the smallest
// eigenvalue of any curved surface, so that a flat or developable patch,
// whose A has parallel fields in its kernel, factors too). Starts from
// u_f = 1 in every triangle's frame: intrinsic, so moving the surface
// rigidly changes nothing.
ComplexVector smallest_eigenvector(const ComplexMatrix& a, const Eigen::VectorXd& mass,
                                   int max_iterations, int& iterations) {
  const double mean_ratio = a.diagonal().real().sum() / mass.sum();
  ComplexMatrix shifted = a;
  for (Eigen::Index f = 0; f < mass.size(); ++f)
    shifted.coeffRef(f, f) += 1e-6 * mean_ratio * mass[f];
  Eigen::SimplicialLDLT<ComplexMatrix, Eigen::Lower> solver(shifted);
  if (solver.info() != Eigen::Success)
    throw std::logic_error("smoothest_cross_field: the energy matrix did not factor");
  auto m_norm = [&](const ComplexVector& v) {
    return std::sqrt((v.array().abs2() * mass.array()).sum());
  };
  ComplexVector u = ComplexVector::Ones(mass.size());
  u /= m_norm(u);
  iterations = 0;
  while (iterations < max_iterations) {
    ++iterations;
    ComplexVector next = solver.solve((mass.array() * u.array()).matrix());
    next /= m_norm(next);
    // Settled when the new iterate is the old one up to a phase: |<u, next>_M|
    // is 1 then (both have unit M-norm).
    const Complex overlap = (u.conjugate().array() * mass.array() * next.array()).sum();
    u = std::move(next);
    if (1.0 - std::abs(overlap) < 1e-14) break;
  }
  return u;
}

// Per triangle, the fourth power of its principal curvature direction
// weighted by the curvature anisotropy |κ1 − κ2|, in the triangle's frame:
// the edge-based shape operator of Cohen-Steiner and Morvan, Σ β_e |e|/2
// ê êᵀ over the triangle's edges (β the dihedral angle, half of each edge
// to either side) per area. Its trace-free part is c e^{2iθ}; c² / |c| turns
// the 2-fold direction into the cross's 4-fold one. A direction and its
// perpendicular give the same cross, so which principal direction the
// tensor's eigenvector is does not matter.
ComplexVector curvature_guide(const HalfedgeMesh& mesh, const Frames& frames) {
  ComplexVector q = ComplexVector::Zero(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    Complex c = 0.0;
    for (int i = 0; i < mesh.degree(f); ++i) {
      const int h = mesh.face_start(f) + i;
      const int t = mesh.twin(h);
      if (t < 0) continue;
      const Vec3& n1 = frames.normal[at(f)];
      const Vec3& n2 = frames.normal[at(mesh.face(t))];
      const Vec3 e = halfedge_vector(mesh, h);
      const double beta = std::atan2(n1.cross(n2).dot(e.normalized()), n1.dot(n2));
      c += 0.5 * beta * e.norm() * std::polar(1.0, 2.0 * angle_in(frames, f, e));
    }
    c /= frames.area[at(f)];
    if (std::abs(c) > 0.0) q[f] = c * c / std::abs(c);
  }
  return q;
}

// The index of every interior vertex in quarter turns: the field's turning
// across the edges around it plus four times its angle defect (the
// holonomy of the loop of triangles), over 2π. Each edge's jump is
// computed once, for its half-edge h with twin > h, and used with the
// opposite sign from the other side, so that the jumps cancel in the sum
// over all vertices and Poincaré–Hopf holds exactly.
std::vector<int> vertex_indices(const HalfedgeMesh& mesh, const Frames& frames,
                                const ComplexVector& u) {
  std::vector<double> jump(at(mesh.num_halfedges()), 0.0);
  for (int h = 0; h < mesh.num_halfedges(); ++h) {
    const int t = mesh.twin(h);
    if (t < h) continue;
    const Complex moved = transport(mesh, frames, h) * u[mesh.face(h)];
    jump[at(h)] = std::arg(u[mesh.face(t)] * std::conj(moved));
    jump[at(t)] = -jump[at(h)];
  }
  std::vector<double> turning(at(mesh.num_vertices()), 0.0);
  std::vector<double> defect(at(mesh.num_vertices()), 2.0 * kPi);
  for (int h = 0; h < mesh.num_halfedges(); ++h) {
    // Counter-clockwise round from(h), the triangle after face(h) lies
    // across prev(h).
    const auto v = at(mesh.from(h));
    defect[v] -= mesh.corner_angle(h);
    turning[v] += jump[at(mesh.prev(h))];
  }
  std::vector<int> index(at(mesh.num_vertices()), 0);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.is_boundary_vertex(v)) continue;
    const double quarter_turns = (turning[at(v)] + kSymmetry * defect[at(v)]) / (2.0 * kPi);
    index[at(v)] = static_cast<int>(std::lround(quarter_turns));
    if (std::abs(quarter_turns - index[at(v)]) > 1e-6) {
      throw std::logic_error("smoothest_cross_field: vertex " + std::to_string(v) + " has index " +
                             std::to_string(quarter_turns) + ", not an integer");
    }
  }
  return index;
}

}  // namespace

PolygonMesh fan_triangulated(const PolygonMesh& mesh) {
  std::set<std::pair<int, int>> edges;
  for (const auto& face : mesh.faces) {
    for (std::size_t i = 0; i < face.size(); ++i)
      edges.insert(std::minmax(face[i], face[(i + 1) % face.size()]));
  }
  PolygonMesh tri;
  tri.positions = mesh.positions;
  // How flat the flattest triangle of the fan from corner k is: twice its
  // area over its longest side squared (0 for three points on a line).
  auto fan_shape = [&](const std::vector<int>& face, std::size_t k) {
    const std::size_t n = face.size();
    double least = std::numeric_limits<double>::infinity();
    for (std::size_t i = 1; i + 1 < n; ++i) {
      const Vec3& a = mesh.positions[at(face[k])];
      const Vec3& b = mesh.positions[at(face[(k + i) % n])];
      const Vec3& c = mesh.positions[at(face[(k + i + 1) % n])];
      const double longest =
          std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
      least = std::min(least, longest > 0.0 ? (b - a).cross(c - a).norm() / longest : 0.0);
    }
    return least;
  };
  // A polygon with a straight corner (a vertex on the line between its
  // neighbours, as where a quad meets two smaller ones) fanned from the
  // wrong corner gives a triangle of no area, which has no normal for a
  // field's frame and whose subdivision puts samples on top of each other.
  constexpr double kFlat = 0.01;
  for (const auto& face : mesh.faces) {
    const std::size_t n = face.size();
    std::size_t start = 0;
    double best = -1.0;  // the chosen fan's shape; below 0 while none is chosen
    for (std::size_t k = 0; k < n && n > 3; ++k) {
      bool free = true;
      for (std::size_t i = 2; i + 1 < n; ++i)
        free = free && edges.count(std::minmax(face[k], face[(k + i) % n])) == 0;
      if (!free) continue;
      // The first free corner, unless its fan is flat: then the first free
      // corner whose fan is not, else the least flat.
      const double shape = fan_shape(face, k);
      if (best < kFlat && shape > best) {
        start = k;
        best = shape;
      }
      if (best >= kFlat) break;
    }
    for (std::size_t i = 2; i + 1 < n; ++i)
      edges.insert(std::minmax(face[start], face[(start + i) % n]));
    for (std::size_t i = 1; i + 1 < n; ++i)
      tri.faces.push_back({face[start], face[(start + i) % n], face[(start + i + 1) % n]});
  }
  return tri;
}

CrossField smoothest_cross_field(const PolygonMesh& surface, const CrossFieldParams& params) {
  CrossField result;
  // Triangulated first, so that resample's own fans see triangles only.
  const PolygonMesh triangles = fan_triangulated(surface);
  result.surface = params.edge_mm > 0.0 ? resample(triangles, params.edge_mm) : triangles;
  const HalfedgeMesh mesh(result.surface);
  const Frames frames = triangle_frames(mesh);
  const ComplexMatrix a = energy_matrix(mesh, frames);
  const Eigen::VectorXd mass = Eigen::Map<const Eigen::VectorXd>(
      frames.area.data(), static_cast<Eigen::Index>(frames.area.size()));

  ComplexVector u;
  if (params.curvature_weight > 0.0) {
    const double edge = params.edge_mm > 0.0 ? params.edge_mm : mean_edge_length(result.surface);
    ComplexMatrix shifted = a;
    for (Eigen::Index f = 0; f < mass.size(); ++f)
      shifted.coeffRef(f, f) += params.curvature_weight / (edge * edge) * mass[f];
    Eigen::SimplicialLDLT<ComplexMatrix, Eigen::Lower> solver(shifted);
    if (solver.info() != Eigen::Success)
      throw std::logic_error("smoothest_cross_field: the guided system did not factor");
    const ComplexVector q = curvature_guide(mesh, frames);
    u = solver.solve((mass.array() * q.array()).matrix());
  } else {
    u = smallest_eigenvector(a, mass, params.max_iterations, result.iterations);
  }
  result.energy = rayleigh_quotient(a, mass, u);

  const std::size_t nf = at(mesh.num_faces());
  result.field.resize(nf);
  result.direction.resize(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const Complex value = u[static_cast<Eigen::Index>(f)];
    result.field[f] = std::abs(value) > 0.0 ? value / std::abs(value) : Complex(1.0);
    const double phi = std::arg(result.field[f]) / kSymmetry;
    result.direction[f] = std::cos(phi) * frames.x[f] + std::sin(phi) * frames.y[f];
  }
  const ComplexVector unit = Eigen::Map<const ComplexVector>(
      result.field.data(), static_cast<Eigen::Index>(result.field.size()));
  result.index = vertex_indices(mesh, frames, unit);
  result.euler_characteristic = mesh.euler_characteristic();
  result.boundary_loops = mesh.count_boundary_loops();
  if (result.boundary_loops == 0) {
    const FieldSingularities s = field_singularities(result);
    if (s.index_sum != kSymmetry * result.euler_characteristic) {
      throw std::logic_error(
          "smoothest_cross_field: indices sum to " + std::to_string(s.index_sum) +
          " on a closed surface of χ = " + std::to_string(result.euler_characteristic));
    }
  }
  return result;
}

FieldSingularities field_singularities(const CrossField& field) {
  FieldSingularities s;
  for (const int index : field.index) {
    if (index == 0) continue;
    ++s.count;
    s.index_sum += index;
    ++s.by_index[index];
  }
  return s;
}

}  // namespace planner
