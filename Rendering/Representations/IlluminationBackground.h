/**
 * @file IlluminationBackground.h
 * @brief Illumination updates off the render call: a worker thread per representation.
 *
 * A representation with AsynchronousLighting hands each still render's lighting to a
 * BackgroundLighting as a job (Start) and draws the last finished illumination meanwhile; the
 * job runs on a thread of its own, publishes what it computed, and the representation takes
 * it (Take) at the start of a later render. Something outside the render asks for that
 * render: in the GUI the plugin's pqIlluminationLightingBehavior, which polls
 * vtkIlluminationStatus (the state of every BackgroundLighting of the process) as ParaView's
 * own streaming behaviour polls its views; in a script, the script (IlluminationPending).
 *
 * A new job supersedes the one queued and cancels the one running: the running job's filter
 * sees the cancellation at its next progress report (between slices; Job::Update sets the
 * filter's AbortExecute), keeps its previous output and publishes nothing. Cancel stops
 * everything without a replacement.
 *
 * Thread safety: VTK pipelines are not thread-safe, so a job owns what it reads (copies of
 * the transfer functions, a shallow copy of the data whose arrays nothing writes while it
 * runs, light values) and the filters it updates, which the render thread touches only
 * while no job runs (Run waits for that). A result is a new data object (a shallow copy of
 * the filter's output, whose arrays every update allocates anew), handed over whole.
 *
 * Run executes a job on the calling thread instead (synchronous lighting, and parallel
 * runs whose filters talk to the other processes), its progress forwarded to the
 * representation as before.
 */
#ifndef IlluminationBackground_h
#define IlluminationBackground_h

#include "IlluminationFilterSupport.h" // for volillum::UpdateReport
#include "vtkDataObject.h"
#include "vtkSmartPointer.h"
#include "vtkWeakPointer.h"

#include <atomic>
#include <condition_variable>
#include <functional>
#include <map>
#include <mutex>
#include <thread>

class vtkAlgorithm;
class vtkColorTransferFunction;
class vtkDataSet;
class vtkPiecewiseFunction;

namespace volillum
{

class BackgroundLighting
{
public:
  /// What a job hands back.
  struct Result
  {
    vtkSmartPointer<vtkDataObject> Data; // the illumination to draw; nullptr: none
    bool Final = true;                   // false: a coarse stage, the final one follows
    bool Unchanged = false;              // the last result still holds (Data is not set)
    UpdateReport Report;
    double Seconds = 0.0; // the filter's wall time
    int Kind = 0;         // what the job's owner asked for, in its own terms
  };

  /// What a job is given: its filters' updates, its results, whether it should stop.
  class Job
  {
  public:
    /**
     * Update a filter: its progress is reported (to the representation when run inline,
     * to Progress() otherwise) and the job's cancellation checked at each report. False
     * when cancelled (the filter keeps its previous output and re-executes next time).
     */
    bool Update(vtkAlgorithm* filter);
    /// Hand a result to the render thread (replaces one it has not taken yet).
    void Publish(const Result& result);
    /**
     * Update `coarse` (when given; its output published as a coarse stage) and then
     * `filter` (published as the final result), stopping when cancelled. `lit` tells whether
     * an output holds something to draw (a final one without is published as nothing to
     * draw); an output whose time is `published`, that of the last final result, is
     * published as Unchanged; `published` is updated. Results carry `kind`.
     */
    void RunStages(vtkAlgorithm* coarse, vtkAlgorithm* filter, int kind, vtkMTimeType& published,
      const std::function<bool(vtkDataObject*)>& lit);
    bool Cancelled() const;

  private:
    friend class BackgroundLighting;
    Job(BackgroundLighting* owner, vtkAlgorithm* progressTo)
      : Owner(owner)
      , ProgressTo(progressTo)
    {
    }
    BackgroundLighting* Owner;
    vtkAlgorithm* ProgressTo; // inline: the representation whose progress bar moves
  };
  using Work = std::function<void(Job&)>;

  BackgroundLighting();
  ~BackgroundLighting();
  BackgroundLighting(const BackgroundLighting&) = delete;
  BackgroundLighting& operator=(const BackgroundLighting&) = delete;

  /// Run work on the worker thread: it replaces a queued job and cancels the running one.
  void Start(Work work);
  /// Run work now on this thread, after cancelling and waiting for the worker's job.
  void Run(const Work& work, vtkAlgorithm* progressTo);
  /// Drop the queued job and cancel the running one (results already published stay).
  void Cancel();
  /// Drop a published result not taken yet (the representation will not draw it).
  void Discard();
  /// Cancel, and wait until no job runs.
  void Stop();

  /// The newest published result not taken yet; false when there is none.
  bool Take(Result& result);
  /// A job runs or is queued.
  bool Busy() const;
  /// A published result waits to be taken.
  bool Ready() const;
  /// The running job's progress, 0 to 1.
  double Progress() const { return this->Fraction.load(); }

  /// Over every BackgroundLighting of the process (vtkIlluminationStatus).
  static bool AnyBusy();
  static bool AnyReady();
  /// Results published by every job of the process so far (a render shows new ones).
  static unsigned int Publications();
  /// Calls of Run (the work run on the calling thread), and jobs that a caller of Stop or Run
  /// or the destructor waited for, by every BackgroundLighting of the process so far.
  static unsigned int Waits();
  static double LeastProgress();
  static void CancelAll();

private:
  void Loop();

  mutable std::mutex Mutex;
  std::condition_variable Changed;
  std::thread Worker;
  Work Queued;
  bool Running = false;
  bool Quit = false;
  std::atomic<bool> CancelRequested{ false };
  std::atomic<double> Fraction{ 0.0 };
  Result Latest;
  bool HasLatest = false;
};

/**
 * What a job reads, owned by it: copies of the transfer functions and a shallow copy of the
 * data (its arrays shared, read only), each made anew only when its original changed, so
 * that a filter sees a change exactly when the original changed.
 */
class JobCopies
{
public:
  vtkSmartPointer<vtkColorTransferFunction> Color(vtkColorTransferFunction* original);
  vtkSmartPointer<vtkPiecewiseFunction> Opacity(vtkPiecewiseFunction* original);
  vtkSmartPointer<vtkDataSet> Data(vtkDataSet* original);

private:
  template <class T>
  struct Copy
  {
    vtkWeakPointer<T> Original;
    vtkMTimeType Time = 0;
    vtkSmartPointer<T> Owned;
  };
  Copy<vtkColorTransferFunction> ColorCopy;
  Copy<vtkPiecewiseFunction> OpacityCopy;
  Copy<vtkDataSet> DataCopy;
};

/**
 * Measured wall times per illumination point of finished lightings by the kind of change that
 * caused them (the caller's key: for instance -1 for everything, n for n lights), and how a
 * new one of a kind, its time expected from that, is best run with AsynchronousLighting:
 *  - Now: expected within 0.2 s, it is computed in the render (no preview frame to pay for);
 *  - Background: on the worker thread, the final lighting alone;
 *  - CoarseFirst: expected over 1 s, a coarse lighting is shown first. Below that, the
 *    coarse stage's own frame costs more than it shows: measured on the engine at 256^3 (2
 *    cores), a one-light edit (0.33 s) with a coarse stage drew its final frame 1.47x later
 *    than synchronously.
 * Without a measurement of the kind, the last time of -1 (everything) bounds it; without
 * either, `points` over a million is expected to take over 1 s.
 */
class LightingCosts
{
public:
  enum class Plan
  {
    Now,
    Background,
    CoarseFirst
  };
  /// A final result taken: the time per point of the lighting that made it, by its Kind.
  void Record(const BackgroundLighting::Result& result);
  /// How to run a lighting of `points` illumination points.
  Plan Choose(int kind, double points) const;

private:
  std::map<int, double> SecondsPerPoint;
};

/**
 * What a representation shows of its background lighting: the last final result it took,
 * whether the one it draws is final, and what its lightings cost.
 */
struct ShownLighting
{
  vtkSmartPointer<vtkDataObject> LastFinal; // the last final result taken
  bool Final = true;                        // the drawn result is a final one
  LightingCosts Costs;

  /// A final result taken for drawing becomes LastFinal, its report and time become the
  /// representation's (`report`, `seconds`) and its cost is recorded; a coarse result changes
  /// none of them.
  void KeepFinal(const BackgroundLighting::Result& result, UpdateReport& report, double& seconds);
};

}

#endif
