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
 *   concavities. The paper solves the steady convection equation there with first-order
 *   upwinding; its numerical diffusion (a shadow spreads by about a cell per cell crossed
 *   obliquely) dominated the two-level error, above that of resampling the mesh and
 *   propagating on the grid (volillum-unstructured-benchmark, issue 46). Level 0 is
 *   therefore the project's ray propagation (LightPropagationKernel.h: light followed along
 *   rays, read at each slice with a bicubic interpolation), one channel at a time, for a
 *   white light without its spot cone: the transmittance. Light enters through the grid
 *   faces, at the mesh bounds, unattenuated.
 * - Level 1: a semi-Lagrangian step of length L from every vertex x:
 *   rho(x) = rho0(x_d) exp(-integral of sigma) with x_d = x - L u, the level-0 light
 *   interpolated trilinearly at the departure point and the optical depth of the segment
 *   integrated exactly for the piecewise-linear extinction (trapezoid per tetrahedron the
 *   walk from x toward the light crosses through their face neighbours). The paper takes
 *   such steps one mean edge long, each reading the previous step's values interpolated in
 *   the tetrahedron of the departure point; n of them are composed here into one walk of n
 *   mean edges, so the level-0 light is interpolated once, where it is farthest from the
 *   vertex, instead of blurring the light n times (with the ray level 0, on the blunt fin
 *   at 128^3, the per-vertex RMS against a brute-force march fell from 2.2 % with steps of
 *   one mean edge to 1.5 %). The default walks
 *   Level1Cells level-0 cells. Where the walk leaves the mesh (a concavity, a hole), the
 *   level-0 light at the exit point carries the rest; where it reaches a point light, 1.
 *   A boundary vertex the light enters the mesh at takes the light outside the mesh: the
 *   level-0 light interpolated from the blank grid points around it alone (grid points
 *   inside the mesh would mix in light already attenuated by up to a level-0 cell, by an
 *   amount that depends on where the boundary cuts the grid: scallops along a curved
 *   surface). Every other vertex walks, on the boundary too (its walk reads no value
 *   interpolated across the tetrahedra, only the level-0 light where it ends).
 * - Lights combine with their radiance and spot-cone factor (eq. 9), and scattering is
 *   one implicit diffusion step solved by Gauss-Seidel iterations of eq. 12 with weights
 *   (mean edge / distance)^2 between mesh neighbours (scale-free strength per channel).
 *   Vertices are greedily coloured so that no two neighbours share a colour; one colour
 *   at a time is updated in parallel, which is exactly a sequential Gauss-Seidel sweep in
 *   colour order.
 *
 * Distributed meshes (a process's piece and the tetrahedra of other pieces near it): the
 * level-0 grid is global (ResampleLevel0Onto of the piece's own tetrahedra, combined over
 * the processes by the caller); the level-1 walk from a vertex reads the mesh within its
 * length of it (Level1Length), and the caller takes the values of other processes'
 * vertices from them after level 1 (PropagateLevel1's exchange), as it does between the
 * rounds of the colouring and the colours of the scattering.
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

/// Ray propagation of one light on the level-0 grid: transmittance, Channels per point.
VOLILLUMKERNELS_EXPORT void PropagateLevel0(
  const Level0Grid& grid, const LightState& light, std::vector<float>& rho);

/// Level-1 semi-Lagrangian solution of one light from its level-0 solution: a walk of
/// `iterations` steps of stepLength toward the light (stepLength <= 0: the mean edge length;
/// iterations <= 0: none, level 0 only). exchange(rho), when given, runs after it (a
/// parallel run replaces the values of other processes' vertices with theirs).
VOLILLUMKERNELS_EXPORT void PropagateLevel1(const TetrahedralMesh& mesh,
  const std::vector<float>& extinction, const Level0Grid& grid, const std::vector<float>& level0,
  const LightState& light, double stepLength, int iterations, std::vector<float>& rho,
  const std::function<void(std::vector<float>& rho)>& exchange = {});

/// Level-0 cells the default level-1 walk spans.
constexpr double Level1Cells = 4.0;

/// Number of level-1 steps of a mean edge that span Level1Cells cells of the level-0 grid
/// `level0` (at least 1).
VOLILLUMKERNELS_EXPORT int AutomaticLevel1Iterations(
  const TetrahedralMesh& mesh, const GridGeometry& level0);

/// Length of the level-1 walk of `iterations` steps of a mean edge (AutomaticLevel1Iterations
/// when negative): how far from a vertex level 1 reads the mesh.
VOLILLUMKERNELS_EXPORT double Level1Length(
  const TetrahedralMesh& mesh, const GridGeometry& level0, int iterations);

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
