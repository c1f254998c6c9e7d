/**
 * @class vtkMultiLightIlluminationVolume
 * @brief Illumination volume for many lights by coherence-based propagation with selective
 * light updates (the selective-light-updates paper, sections 4-5).
 *
 * Lights are grouped by the six axis directions they travel (see LightPropagationKernel.h);
 * every light of a group is swept through the volume in the same pass with its own pair of
 * 2D slice buffers, and all contributions are accumulated in one illumination volume, so
 * memory does not grow with the number of lights beyond those buffers.
 *
 * The filter remembers the light states it has applied. When only lights changed since the
 * last update it can remove the old states and add the new ones (selective update) instead
 * of recomputing every light (full update); a change of the data, the transfer functions,
 * the unit distance, the attenuation mode or the resolution forces a full update. Which of
 * the two runs is decided by CostEstimate:
 * - ChangedLightFraction: selective when at most half of the lights changed;
 * - PropagationPasses (default): selective unless it is estimated to cost more than a full
 *   update (volillum::EstimatePropagationCost): the sweeps each would run (lights sharing a
 *   sweep's group once per sweep, as it runs them; a removal and an addition of the same rays,
 *   a colour change, one propagation), the light geometries each sweep propagates (a point
 *   or spot light's rays cost more than a directional light's), their deposits, and the
 *   record's bookkeeping (a record started, its deposits, one subtracted) against clearing
 *   the illumination. So with two lights a light moved once is recomputed with the other
 *   (three sweeps either way, and no record to start), with more lights it is removed and
 *   added. A light changed alone twice in a row is taken as dragged: it is recorded when
 *   adding its new state alone (what each later update of the drag does, subtracting the
 *   record) costs no more than a full update, and a recorded light only adds its new state.
 * UpdateMode (0 full, 1 selective) and PropagationPasses (sweeps done) in the output's field
 * data report the choice. The illumination is kept in 32-bit fixed point (a unit chosen from
 * the lights' summed radiance, see FixedPointIllumination), so a selective update cancels
 * an old light state exactly: any number of selective updates equals a full recompute of
 * the final lights up to float rounding of the output. A light brightened or dimmed beyond
 * what the unit suits makes the update a full one with a new unit.
 *
 * With RecordEditedLight (default on) the last light changed alone is recorded: its
 * contribution is kept beside the total (12 bytes per illumination point) until a full
 * update. When that light changes again, as it does while it is dragged, its old state is
 * removed by subtracting the record instead of propagating it again: only the new state is
 * propagated (and recorded), with the same exact result. A full update releases the record before
 * it allocates, so its peak memory is unchanged; a selective update that records needs those 12
 * bytes per point more.
 *
 * MaximumPassesPerUpdate limits the sweeps of one update for progressive refinement: the
 * rest is kept (field array PendingPasses) and done by the next update (call Modified()
 * and Update() again, or press Apply). An aborted update keeps the previous output and
 * makes the next update a full one; a parallel update (see
 * vtkIlluminationVolumeAlgorithm::SetController) is not aborted.
 *
 * Method: E. Sundén and T. Ropinski, "Efficient Volume Illumination with Multiple Light Sources
 * through Selective Light Updates", IEEE Pacific Visualization Symposium (PacificVis), 2015.
 *
 * @sa vtkFilteredVolumetricShadows vtkRayMarchedIllumination vtkIlluminatedVolumeMapper
 */
#ifndef vtkMultiLightIlluminationVolume_h
#define vtkMultiLightIlluminationVolume_h

#include "LightPropagationKernel.h"
#include "vtkIlluminationVolumeAlgorithm.h"

class VOLILLUMFILTERS_EXPORT vtkMultiLightIlluminationVolume : public vtkIlluminationVolumeAlgorithm
{
public:
  static vtkMultiLightIlluminationVolume* New();
  vtkTypeMacro(vtkMultiLightIlluminationVolume, vtkIlluminationVolumeAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum CostEstimates
  {
    ChangedLightFraction = 0,
    PropagationPasses = 1
  };

  ///@{
  /** How a light change chooses between a selective and a full update. Default PropagationPasses.
   */
  vtkSetClampMacro(CostEstimate, int, ChangedLightFraction, PropagationPasses);
  vtkGetMacro(CostEstimate, int);
  ///@}

  ///@{
  /** Allow selective updates (default on); off recomputes every light on every update. */
  vtkSetMacro(SelectiveUpdates, bool);
  vtkGetMacro(SelectiveUpdates, bool);
  vtkBooleanMacro(SelectiveUpdates, bool);
  ///@}

  ///@{
  /**
   * Propagate all lights of a group in one sweep (default on); off sweeps once per light
   * (the sequential propagation the paper compares with). The results are identical.
   */
  vtkSetMacro(CoherentPropagation, bool);
  vtkGetMacro(CoherentPropagation, bool);
  vtkBooleanMacro(CoherentPropagation, bool);
  ///@}

  ///@{
  /** Most sweeps one update may do (0, the default: no limit). */
  vtkSetClampMacro(MaximumPassesPerUpdate, int, 0, VTK_INT_MAX);
  vtkGetMacro(MaximumPassesPerUpdate, int);
  ///@}

  ///@{
  /**
   * Record a light changed alone, so that its next change alone subtracts its old state
   * instead of propagating it (default on; see above). Off releases the record at the next
   * update.
   */
  vtkSetMacro(RecordEditedLight, bool);
  vtkGetMacro(RecordEditedLight, bool);
  vtkBooleanMacro(RecordEditedLight, bool);
  ///@}

  ///@{
  /**
   * In a parallel run (default on): sweep the light over bands of the
   * grid instead of assembling the whole input on every process. A sweep computes its slices
   * row by row; the rows are shared out in bands, one per process with a piece (at least a
   * row each). A process gets the classification of its band from the others' blocks, every
   * process sweeps all slices of its rows at once, and after each slice a band gets the
   * lattice rows either side of its own that a directional light's rays move across between
   * slices and a bicubic read takes (LatticeHalo) from the bands that hold them (bands up to
   * ceil(halo / rows a band) away when bands are thinner than the halo); the units
   * go to the processes whose pieces hold them. A point or spot light sweeps apart from the
   * directional lights, over wedges of its rays (volillum::SplitIntoWedges: the points whose
   * ratio of row to distance from the light, constant along a ray, lies in a range, about as
   * many in each): a process gets the classification of its wedge and the cone margin around
   * it slice by slice, sweeps it alone (no ray leaves a wedge, so nothing is exchanged) and
   * sends its units, slice by slice, to the processes whose pieces hold them. Memory per
   * process follows its block, band and wedge (the lattices hold the band's rows and halo; a
   * point or spot light's ray buffers the rows of the wedge's cone).
   * Off, the input is assembled and the sweeps shared out (see
   * vtkIlluminationVolumeAlgorithm::SetController). The result equals the serial run's.
   */
  vtkSetMacro(DistributedSweeps, bool);
  vtkGetMacro(DistributedSweeps, bool);
  vtkBooleanMacro(DistributedSweeps, bool);
  ///@}

  /// The points of the largest band or wedge of the classification this process held in the
  /// last parallel update with DistributedSweeps (0 otherwise; field array BandPoints).
  long long GetLastBandPoints() const { return this->BandPoints; }

  /// The bytes this process sent in the last parallel update with DistributedSweeps: the
  /// classification of its block in others' bands, lattice rows and units (field array
  /// SentBytes).
  long long GetLastSentBytes() const { return this->SentBytes; }

  /// Sweeps left for later updates by MaximumPassesPerUpdate.
  int GetNumberOfPendingPasses() const;

  /// Largest total of 2D slice buffers the last update had alive at once, in bytes.
  size_t GetLastPeakBufferBytes() const { return this->LastStatistics.PeakBufferBytes; }

  /// Light propagations (tasks swept: one per light and group) of the last update.
  long long GetLastLightPropagations() const { return this->LastStatistics.LightSweeps; }

  /// The light whose contribution is recorded (see above), -1 when none is.
  int GetRecordedLight() const { return this->RecordedLight; }

  /**
   * The estimated costs (volillum::PropagationCost: nanoseconds per illumination point) of
   * the selective and of the full update that the last update chose between with
   * PropagationPasses; -1 where it had no choice (a full update was needed, or another
   * CostEstimate).
   */
  double GetLastSelectiveCost() const { return this->LastSelectiveCost; }
  double GetLastFullCost() const { return this->LastFullCost; }

protected:
  vtkMultiLightIlluminationVolume() = default;
  ~vtkMultiLightIlluminationVolume() override = default;

  bool ComputeIllumination(const volillum::ClassifiedVolume& volume,
    const std::vector<volillum::LightState>& lights, const volillum::GridGeometry& target,
    bool inputModified, float* rgb, UpdateReport& report) override;
  bool LightsDistributedPieces() const override { return this->DistributedSweeps; }
  /// Field arrays BandPoints and SentBytes after a parallel update over bands.
  void AddOutputFieldData(vtkFieldData* fieldData) override;
  void ComputeDistributedIllumination(vtkMultiProcessController* controller,
    const volillum::ClassifiedVolume& volume, const volillum::VolumePiece& piece,
    const std::vector<volillum::LightState>& lights, const volillum::GridGeometry& target,
    const std::vector<int>& extents, bool inputModified, float* rgb, UpdateReport& report) override;

  int CostEstimate = PropagationPasses;
  bool SelectiveUpdates = true;
  bool CoherentPropagation = true;
  int MaximumPassesPerUpdate = 0;
  bool RecordEditedLight = true;
  bool DistributedSweeps = true;

private:
  vtkMultiLightIlluminationVolume(const vtkMultiLightIlluminationVolume&) = delete;
  void operator=(const vtkMultiLightIlluminationVolume&) = delete;

  // What a selective update does with the record (RecordEditedLight). When the recorded light
  // changes (with others or not), its old state leaves by subtracting the record (Subtracted)
  // and its new state is recorded (Record); otherwise a light changed alone is recorded
  // instead, or the record is kept (Kept). A full update drops it.
  struct RecordPlan
  {
    int Subtracted = -1;
    int Record = -1;
    int Kept = -1;
  };
  RecordPlan PlanRecord(const std::vector<int>& changed, size_t lights) const;
  // Whether the selective update (its tasks and record plan) runs instead of the full one
  // (CostEstimate); sets LastSelectiveCost and LastFullCost. dragged: the light changed
  // alone was also the one changed alone by the update before.
  bool ChooseSelective(const std::vector<volillum::PropagationTask>& selective,
    const RecordPlan& plan, const std::vector<volillum::PropagationTask>& full, size_t changed,
    size_t lights, bool dragged);
  double LastSelectiveCost = -1.0, LastFullCost = -1.0;
  int LoneLight = -1; // the light the last update found changed alone, -1: none
  // Subtracts, starts or drops the record as planned, before the propagation.
  void StartRecord(const RecordPlan& plan);
  // Sets RecordedLight after the propagation (or drops the record) and clears the Recorded
  // flags of the tasks left for later.
  void FinishRecord(const RecordPlan& plan, std::vector<volillum::PropagationTask>& remaining);

  // Whether an update of `points` illumination points must recompute every light.
  bool MustRecompute(const std::vector<volillum::LightState>& lights, long long points,
    bool inputModified, bool distributed) const;
  // The work of an update (the tasks of every light for a full one, else the pending work and
  // the changed lights' removals and additions); starts the record as planned and resets the
  // illumination to `points` points for a full update. Returns whether it is selective.
  bool PrepareUpdate(const std::vector<volillum::LightState>& lights, const double bounds[6],
    long long points, bool mustRecompute, std::vector<volillum::PropagationTask>& work,
    RecordPlan& plan);
  // The bookkeeping of a complete update and its report.
  void CommitUpdate(bool selective, const RecordPlan& plan,
    std::vector<volillum::PropagationTask>& remaining,
    const std::vector<volillum::LightState>& lights, bool distributed, UpdateReport& report);
  // The accumulated illumination and the states it holds (with Pending still to do).
  volillum::FixedPointIllumination Illumination;
  volillum::LightChangeTracker Applied;
  std::vector<volillum::PropagationTask> Pending;
  bool Valid = false;
  int RecordedLight = -1; // whose contribution Illumination.Recorded holds
  // Whether Illumination holds this process's extent of a parallel run over bands (else the
  // whole grid).
  bool DistributedLayout = false;
  long long BandPoints = 0;
  long long SentBytes = 0;
  volillum::PropagationStatistics LastStatistics;
};

#endif
