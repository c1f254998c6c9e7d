/**
 * @file DistributedPropagation.h
 * @brief Multi-light propagation over the processes of a parallel run, without assembling
 * the input: directional lights sweep over bands of rows, point and spot lights over wedges of
 * their rays.
 *
 * Each process holds the classification of its block of the data and an illumination over its
 * own extent of the illumination grid (fixed-point units, FixedPointIllumination). A sweep of
 * directional tasks runs over bands of its rows, one band per process with a piece: a band gets
 * the classification it reads from the blocks (ExchangeExtents), and after every slice the
 * lattice rows it reads beyond its own from the bands that hold them. A point or spot light
 * sweeps over wedges of its rays (SplitIntoWedges), each process its wedge's classification
 * slice by slice. The units of every band and wedge go to the processes whose extents hold
 * them. The sums are exact in any order, so the result equals a serial run's bit for bit.
 */
#ifndef DistributedPropagation_h
#define DistributedPropagation_h

#include "LightPropagationKernel.h"
#include "RayMarchKernel.h"
#include "VolIllumParallelModule.h"

#include <functional>
#include <vector>

class vtkMultiProcessController;

namespace volillum
{

class VOLILLUMPARALLEL_EXPORT DistributedPropagation
{
public:
  /// The processes with a piece (a non-empty extent of the illumination grid in `extents`, 6
  /// values a process, as GatherExtents gives them) sweep; the others take part in the
  /// collective calls only.
  DistributedPropagation(vtkMultiProcessController* controller, const std::vector<int>& extents);

  /// Whether this process sweeps (has a piece).
  bool Sweeps() const { return this->Me >= 0; }

  /**
   * Collective: the sweeps (PlanSweeps's; none where this process does not sweep) propagated
   * over the whole grid, their units added to `illumination` over this process's extent `own`
   * (and to its record where a task is recorded). `volume` and `piece`: this process's block of
   * the classification; `target`: the whole illumination grid. `progress` is told the fraction
   * of the sweeps done.
   */
  void Propagate(const ClassifiedVolume& volume, const VolumePiece& piece,
    const GridGeometry& target, const std::vector<std::vector<PropagationTask>>& sweeps,
    const int own[6], FixedPointIllumination& illumination, PropagationStatistics& statistics,
    const std::function<void(double)>& progress);

  /// The largest number of classified points a band or wedge of this process held.
  long long GetBandPoints() const { return this->BandPoints; }
  /// The bytes this process sent.
  long long GetSentBytes() const { return this->SentBytes; }

private:
  // What every sweep shares: its data, the results and the progress over all sweeps.
  struct Context
  {
    const ClassifiedVolume& Volume;
    const VolumePiece& Piece;
    const GridGeometry& Target;
    const int* Own;
    bool Record;
    FixedPointIllumination& Illumination;
    PropagationStatistics& Statistics;
    std::function<void(double)> Progress; // of the current sweep's slices
    size_t Swept;
    size_t Total;
  };
  // Collective: the sweeps (of directional tasks) whose rows lie along `rowAxis`, over bands
  // of those rows.
  void SweepBands(
    Context& context, int rowAxis, const std::vector<std::vector<PropagationTask>>& sweeps);
  // Collective: after a slice, each band's lattice rows sent to the bands whose windows (their
  // rows and `band.Halo` either side) meet them, and theirs received.
  void ExchangeLatticeRows(const SweepBand& band, int rows, int count,
    const std::vector<float*>& lattices, size_t rowValues, int firstRow);
  // Collective: the sweeps of one point or spot light each (`groups`: their groups, agreed by
  // all), each over wedges of the light's rays, one a process that sweeps.
  void SweepWedges(Context& context, const std::vector<std::vector<PropagationTask>>& sweeps,
    const std::vector<int>& groups);
  // Collective: the units of a band (over extent `rows`) or of a wedge's chunk added to the
  // processes whose extents hold them (and the record's when recording).
  void MoveUnits(Context& context, const int rows[6], const FixedPointIllumination& units);

  vtkMultiProcessController* Controller;
  std::vector<int> Participants; // the processes that sweep, in process order
  int Me = -1;                   // this process's place among them (-1: none)
  long long BandPoints = 0;
  long long SentBytes = 0;
};

}

#endif
