/**
 * @file DistributedMesh.h
 * @brief The two-level unstructured solver's mesh over the processes of a parallel run: each
 * process's neighbourhood grid (NeighborhoodGrid) as a mesh whose whole-mesh quantities (bounds,
 * mean edge length) and vertex colours are those a single process gives the whole grid.
 */
#ifndef DistributedMesh_h
#define DistributedMesh_h

#include "TetrahedralLightKernel.h"
#include "VolIllumParallelModule.h"

#include <string>

class vtkMultiProcessController;
class vtkUnstructuredGrid;

namespace volillum
{

class NeighborhoodGrid;

/// Collective: the mean length of the tetrahedra's edges over every process's `tetrahedra`
/// (nullptr for none), each tetrahedron's six edges counted; -1 where no process has one.
VOLILLUMPARALLEL_EXPORT double MeanTetrahedronEdge(
  vtkMultiProcessController* controller, vtkUnstructuredGrid* tetrahedra);

/**
 * Collective: `mesh` (this process's neighbourhood, `owned` its points this process owns) gets
 * the whole mesh's bounds (of all processes' own usable tetrahedra: the level-0 grid spans
 * them) and mean edge length (each point's edges counted by its owner). False, with the reason
 * in error, when no process has a tetrahedron with a non-zero volume.
 */
VOLILLUMPARALLEL_EXPORT bool AgreeOnWholeMesh(vtkMultiProcessController* controller,
  TetrahedralMesh& mesh, const std::vector<unsigned char>& owned, std::string& error);

/**
 * Collective: the colours of `mesh`'s vertices as a single process gives them: this process
 * colours the points it computes (`neighborhood.GetComputed()`), in rounds between which the
 * colours of the others come from their processes; every process ends with as many colours.
 * False, with the reason in error, when a round colours no point on any process (a point's
 * colour never comes from the process that holds it).
 */
VOLILLUMPARALLEL_EXPORT bool ColorDistributedVertices(vtkMultiProcessController* controller,
  const NeighborhoodGrid& neighborhood, const TetrahedralMesh& mesh, VertexColoring& coloring,
  std::string& error);

}

#endif
