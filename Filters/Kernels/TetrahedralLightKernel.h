/**
 * @file TetrahedralLightKernel.h
 * @brief Two-level light transport on tetrahedral meshes (Shih, Zhang and Ma), plain C++.
 *
 * Method: M. Shih, Y. Zhang and K.-L. Ma, "Advanced Lighting for Unstructured-Grid Data
 * Visualization", IEEE Pacific Visualization Symposium (PacificVis), 2015: the illumination model
 * (section 3), the two-level light propagation (section 4.1), the combination of lights and the
 * scattering step (section 4.2, eq. 9-12) and the update procedure (Algorithm 1).
 *
 * Light of each source is a transmittance rho (1 unoccluded) per vertex and channel
 * (one channel, or three with chromatic attenuation), the steady state of the convection
 * equation c u . grad(rho) = -sigma_a sigma rho.
 *
 * - Level 0: the mesh's extinction resampled onto a regular grid covering its bounds,
 *   blank (outside every tetrahedron) points transparent, so light crosses holes and
 *   concavities. The steady convection equation is solved with first-order upwinding in
 *   one ordered pass: points are visited in order of distance from the light along each
 *   axis, so every upwind neighbour is final when read. At a point with direction u the
 *   axis weights are w_a = |u_a| / h_a, the upwind step is ds = 1 / sum(w_a), and the
 *   point receives sum(w_a ds rho_a exp(-ds sigma_a')) with sigma_a' the trapezoid mean
 *   of its own and neighbour a's extinction (the exponential form of the upwind update,
 *   exact along an axis). Light enters through the grid faces, at the mesh bounds,
 *   unattenuated.
 * - Level 0 to level 1: the grid solution is interpolated trilinearly onto every vertex as
 *   its initial value.
 * - Level 1: semi-Lagrangian steps rho_{n+1}(x) = rho_n(x_d) (1 - alpha)^{sigma_a} with
 *   x_d = x - s u. The departure point is found by walking tetrahedra through their face
 *   neighbours from x toward the light; rho_n(x_d) is the barycentric interpolation in
 *   the tetrahedron that contains it, and alpha = 1 - exp(-integral of sigma) along the
 *   walked segment, integrated exactly for the piecewise-linear extinction (trapezoid per
 *   tetrahedron crossed). Where the walk leaves the mesh (at once for a boundary vertex
 *   facing the light) the departure value is the level-0 light outside the mesh at the
 *   exit point, interpolated from the blank grid points around it: the inflow boundary
 *   condition. Grid points inside the mesh would mix in light already attenuated by up to
 *   a level-0 cell, by an amount that depends on where the boundary cuts the grid
 *   (scallops along a curved surface). Where the walk reaches a point light, 1. The
 *   vertices inside the mesh take the steps, and so do boundary vertices the light enters
 *   the mesh at (their value is the inflow light); the other boundary vertices (the light
 *   has crossed the mesh to them) keep the level-0 light, which one step of linear
 *   interpolation across tetrahedra larger than the level-0 cells would only blur.
 *   Departure points do not change between steps, so they are found once per light and
 *   each step is a Jacobi update of the vertices.
 * - Lights combine with their radiance and spot-cone factor (eq. 9), and scattering is
 *   one implicit diffusion step solved by Gauss-Seidel iterations of eq. 12 with weights
 *   (mean edge / distance)^2 between mesh neighbours (scale-free strength per channel).
 *   Vertices are greedily coloured so that no two neighbours share a colour; one colour
 *   at a time is updated in parallel, which is exactly a sequential Gauss-Seidel sweep in
 *   colour order.
 *
 * Distributed meshes (a process's piece and the tetrahedra of other pieces near it): the
 * level-0 grid is global (ResampleLevel0Onto of the piece's own tetrahedra, combined over
 * the processes by the caller); a level-1 step at a vertex reads the mesh within one step
 * length of it and the vertices of the tetrahedron it departs from, whose values the
 * caller takes from the other processes after each step (PropagateLevel1's afterStep), as
 * it does between the rounds of the colouring and the colours of the scattering.
 */
#ifndef TetrahedralLightKernel_h
#define TetrahedralLightKernel_h

#include "IlluminationClassification.h"
#include "IlluminationLights.h"
#include "VolIllumKernelsModule.h"

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace volillum
{

/// A tetrahedral mesh prepared for light transport.
struct VOLILLUMKERNELS_EXPORT TetrahedralMesh
{
  std::vector<double> Points; // 3 per point
  std::vector<int> Tets;      // 4 point ids per usable tetrahedron, positively oriented
  std::vector<int> Neighbors; // 4 per tetrahedron: across the face opposite vertex i, -1 none
  std::vector<int> PointTetOffsets, PointTets; // tetrahedra around each point
  std::vector<int> EdgeOffsets, EdgeNeighbors; // mesh neighbours of each point
  std::vector<float> EdgeWeights;              // (mean edge / length)^2 per neighbour entry
  std::vector<unsigned char> Interior;         // 1: used and not on a boundary face
  double Bounds[6] = { 0, 0, 0, 0, 0, 0 };     // of the points of the own tetrahedra
  double MeanEdgeLength = 0.0;
  int OwnTets = 0; // usable tetrahedra among the first `own` given (the first OwnTets here)
  long long Degenerate = 0; // tetrahedra dropped for (near) zero volume
  long long Inverted = 0;   // tetrahedra reoriented

  int NumberOfPoints() const { return static_cast<int>(this->Points.size() / 3); }
  int NumberOfTets() const { return static_cast<int>(this->Tets.size() / 4); }
};

/**
 * Build the mesh from points (3 doubles each) and tetrahedra (4 point ids each).
 * Tetrahedra with |volume| <= 1e-9 x (longest edge)^3 are dropped (their faces become
 * boundary); inverted ones are reoriented. Returns false with a message when nothing
 * usable remains. The first `own` tetrahedra (all when negative) are the mesh's own (a
 * process's piece; the others are its neighbours'): Bounds cover their points. A mesh with
 * own tetrahedra given (own >= 0) may have none (a process with nothing to light).
 */
VOLILLUMKERNELS_EXPORT bool BuildTetrahedralMesh(std::vector<double> points,
  const std::vector<long long>& tets, TetrahedralMesh& mesh, std::string& error,
  long long own = -1);

/// Replace the mean edge length (that of the whole distributed mesh) and the scattering
/// weights that depend on it.
VOLILLUMKERNELS_EXPORT void SetMeanEdgeLength(TetrahedralMesh& mesh, double mean);

/// Level-0 grid: per-channel extinction (0 where blank) on a regular grid over the mesh.
struct VOLILLUMKERNELS_EXPORT Level0Grid
{
  GridGeometry Geometry;
  int Channels = 1;
  std::vector<float> Extinction;     // Channels per point
  std::vector<unsigned char> Inside; // 1 inside a tetrahedron
};

/// The level-0 grid of the given dimensions (at least 2 per axis) spanning bounds.
VOLILLUMKERNELS_EXPORT GridGeometry Level0Geometry(
  const double bounds[6], const std::array<int, 3>& dimensions);

/// Resample per-vertex extinction (channels per vertex) onto a grid of the given
/// dimensions spanning the mesh bounds.
VOLILLUMKERNELS_EXPORT void ResampleLevel0(const TetrahedralMesh& mesh,
  const std::vector<float>& extinction, int channels, const std::array<int, 3>& dimensions,
  Level0Grid& grid);

/// Resample the extinction inside the mesh's own tetrahedra onto `geometry`; points in no
/// own tetrahedron get 0 and are not marked inside.
VOLILLUMKERNELS_EXPORT void ResampleLevel0Onto(const TetrahedralMesh& mesh,
  const std::vector<float>& extinction, int channels, const GridGeometry& geometry,
  Level0Grid& grid);

/// Upwind solution of one light on the level-0 grid: transmittance, Channels per point.
VOLILLUMKERNELS_EXPORT void PropagateLevel0(
  const Level0Grid& grid, const LightState& light, std::vector<float>& rho);

/// Level-1 semi-Lagrangian solution of one light from its level-0 solution.
/// stepLength <= 0 means the mean edge length; iterations < 0 means none (level 0 only).
/// afterStep(rho), when given, runs after each step (a parallel run replaces the values of
/// other processes' vertices with theirs).
VOLILLUMKERNELS_EXPORT void PropagateLevel1(const TetrahedralMesh& mesh,
  const std::vector<float>& extinction, const Level0Grid& grid, const std::vector<float>& level0,
  const LightState& light, double stepLength, int iterations, std::vector<float>& rho,
  const std::function<void(std::vector<float>& rho)>& afterStep = {});

/// Number of level-1 steps that carry light across one level-0 cell (at least 1).
VOLILLUMKERNELS_EXPORT int AutomaticLevel1Iterations(
  const TetrahedralMesh& mesh, const Level0Grid& grid);

/// Eq. 9: rgb (3 per vertex) = sum over lights of radiance x cone factor x rho. rho[i]
/// holds light i's transmittance (channels per vertex), empty for lights that are off.
VOLILLUMKERNELS_EXPORT void CombineLights(const TetrahedralMesh& mesh,
  const std::vector<LightState>& lights, const std::vector<const std::vector<float>*>& rho,
  int channels, std::vector<float>& rgb);

/// Vertices grouped by colour: Order[Offsets[c] .. Offsets[c+1]) have colour c.
struct VertexColoring
{
  std::vector<int> Order;
  std::vector<int> Offsets;
  int NumberOfColors() const { return static_cast<int>(this->Offsets.size()) - 1; }
};

/**
 * Greedy colouring: vertices in an order fixed by their coordinates alone (a hash of them,
 * then the coordinates, then the ids of coincident vertices), each given the smallest
 * colour none of its mesh neighbours earlier in that order has. The order does not follow
 * the mesh's numbering or its pieces, so every process of a parallel run colours its
 * vertices as a single process colours the whole mesh.
 *
 * Parallel: `owned` (1 per vertex) marks the vertices this process colours; the others are
 * other processes'. A vertex is coloured once its earlier neighbours are; between rounds
 * `exchange(color)` fills the colours (-1 when not yet coloured) of the others' vertices
 * from their owners and returns whether to go on (whether any process still has an
 * uncoloured vertex; false also stops a colouring that cannot finish, whose uncoloured
 * vertices are then left out). The order is pseudo-random, so chains of earlier neighbours
 * are short and few rounds run. Only owned vertices are listed in the colouring.
 */
VOLILLUMKERNELS_EXPORT VertexColoring ColorVertices(const TetrahedralMesh& mesh,
  const std::vector<unsigned char>* owned = nullptr,
  const std::function<bool(std::vector<int>& color)>& exchange = {});

/// Eq. 12: one implicit diffusion step of strength[c] per channel, solved by iterations
/// of coloured Gauss-Seidel. rgb holds 3 values per vertex and is updated in place.
/// afterColor(c), when given, runs after the vertices of colour c are updated (a parallel
/// run passes the new values of its vertices to the processes that read them).
VOLILLUMKERNELS_EXPORT void Scatter(const TetrahedralMesh& mesh, const VertexColoring& coloring,
  const std::array<double, 3>& strength, int iterations, std::vector<float>& rgb,
  const std::function<void(int color)>& afterColor = {});

}

#endif
