#include "IlluminationBackground.h"

#include "vtkAlgorithm.h"
#include "vtkCallbackCommand.h"
#include "vtkColorTransferFunction.h"
#include "vtkCommand.h"
#include "vtkDataSet.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"

#include <algorithm>
#include <vector>

namespace
{
// How a lighting runs by its expected time (LightingCosts).
constexpr double NowSeconds = 0.2;
constexpr double CoarseFirstSeconds = 1.0;
// Without a measurement: points above which a lighting is expected to take over 1 s (the
// propagation lights about 5 million points a second per light on 2 cores).
constexpr double CoarseFirstPoints = 1.0e6;

template <class T, class Make>
vtkSmartPointer<T> Renewed(
  T* original, vtkWeakPointer<T>& last, vtkMTimeType& time, vtkSmartPointer<T>& owned, Make make)
{
  if (!original)
  {
    return nullptr;
  }
  if (!owned || original != last || original->GetMTime() != time)
  {
    owned = make(original);
    last = original;
    time = original->GetMTime();
  }
  return owned;
}

template <class T>
vtkSmartPointer<T> DeepCopyOf(T* original)
{
  auto copy = vtkSmartPointer<T>::New();
  copy->DeepCopy(original);
  return copy;
}

// Every BackgroundLighting of the process, for vtkIlluminationStatus.
std::mutex RegistryMutex;
std::atomic<unsigned int> PublishedCount{ 0 }; // results published by every job so far
std::atomic<unsigned int> WaitCount{ 0 };      // lightings a caller ran or waited for
std::vector<volillum::BackgroundLighting*>& Registry()
{
  static std::vector<volillum::BackgroundLighting*> registry;
  return registry;
}
}

namespace volillum
{

//------------------------------------------------------------------------------
bool BackgroundLighting::Job::Cancelled() const
{
  return this->Owner->CancelRequested.load();
}

//------------------------------------------------------------------------------
bool BackgroundLighting::Job::Update(vtkAlgorithm* filter)
{
  struct Watch
  {
    Job* Self;
    vtkAlgorithm* Filter;
  } watch{ this, filter };
  vtkNew<vtkCallbackCommand> observer;
  observer->SetClientData(&watch);
  observer->SetCallback(
    [](vtkObject*, unsigned long, void* clientData, void*)
    {
      auto* w = static_cast<Watch*>(clientData);
      const double fraction = w->Filter->GetProgress();
      w->Self->Owner->Fraction.store(fraction);
      if (w->Self->ProgressTo)
      {
        w->Self->ProgressTo->UpdateProgress(fraction);
      }
      if (w->Self->Cancelled())
      {
        w->Filter->SetAbortExecute(1); // the filter stops at this report
      }
    });
  filter->SetAbortExecute(0);
  const unsigned long tag = filter->AddObserver(vtkCommand::ProgressEvent, observer);
  filter->Update();
  filter->RemoveObserver(tag);
  if (this->Cancelled())
  {
    filter->Modified(); // what was abandoned is computed by the next update
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
void BackgroundLighting::Job::Publish(const Result& result)
{
  std::lock_guard<std::mutex> lock(this->Owner->Mutex);
  if (this->Owner->CancelRequested)
  {
    return; // cancelled or superseded after its last progress report
  }
  this->Owner->Latest = result;
  this->Owner->HasLatest = true;
  ++PublishedCount;
}

//------------------------------------------------------------------------------
void BackgroundLighting::Job::RunStages(vtkAlgorithm* coarse, vtkAlgorithm* filter, int kind,
  vtkMTimeType& published, const std::function<bool(vtkDataObject*)>& lit)
{
  bool coarsePublished = false;
  auto publish = [&](vtkAlgorithm* stage, bool final)
  {
    vtkDataObject* output = stage->GetOutputDataObject(0);
    Result result;
    result.Final = final;
    result.Kind = kind;
    const bool drawable = output && lit(output);
    if (drawable && final && !coarsePublished && output->GetMTime() == published)
    {
      result.Unchanged = true; // drawn already
    }
    else if (drawable)
    {
      // Every update allocates new arrays: the copy shares ones no later update writes.
      result.Data.TakeReference(output->NewInstance());
      result.Data->ShallowCopy(output);
      ReadUpdateFieldData(output->GetFieldData(), result.Report, result.Seconds);
    }
    else if (!final)
    {
      return; // no coarse illumination: wait for the final one
    }
    if (final)
    {
      published = output ? output->GetMTime() : 0;
    }
    this->Publish(result);
  };
  if (coarse)
  {
    if (!this->Update(coarse))
    {
      return;
    }
    publish(coarse, false);
    coarsePublished = true;
  }
  if (this->Update(filter))
  {
    publish(filter, true);
  }
}

//------------------------------------------------------------------------------
BackgroundLighting::BackgroundLighting()
{
  std::lock_guard<std::mutex> lock(RegistryMutex);
  Registry().push_back(this);
}

//------------------------------------------------------------------------------
BackgroundLighting::~BackgroundLighting()
{
  {
    std::lock_guard<std::mutex> lock(RegistryMutex);
    auto& registry = Registry();
    registry.erase(std::remove(registry.begin(), registry.end(), this), registry.end());
  }
  {
    std::lock_guard<std::mutex> lock(this->Mutex);
    if (this->Running)
    {
      ++WaitCount; // joined below
    }
    this->Queued = nullptr;
    this->Quit = true;
    this->CancelRequested = true;
  }
  this->Changed.notify_all();
  if (this->Worker.joinable())
  {
    this->Worker.join();
  }
}

//------------------------------------------------------------------------------
void BackgroundLighting::Start(Work work)
{
  {
    std::lock_guard<std::mutex> lock(this->Mutex);
    this->Queued = std::move(work);
    if (this->Running)
    {
      this->CancelRequested = true;
    }
    if (!this->Worker.joinable())
    {
      this->Worker = std::thread(&BackgroundLighting::Loop, this);
    }
  }
  this->Changed.notify_all();
}

//------------------------------------------------------------------------------
void BackgroundLighting::Loop()
{
  std::unique_lock<std::mutex> lock(this->Mutex);
  while (true)
  {
    this->Changed.wait(lock, [this] { return this->Quit || this->Queued; });
    if (this->Quit)
    {
      return;
    }
    Work work = std::move(this->Queued);
    this->Queued = nullptr;
    this->Running = true;
    this->CancelRequested = false;
    this->Fraction = 0.0;
    lock.unlock();
    Job job(this, nullptr);
    work(job);
    lock.lock();
    this->Running = false;
    this->Changed.notify_all();
  }
}

//------------------------------------------------------------------------------
void BackgroundLighting::Cancel()
{
  std::lock_guard<std::mutex> lock(this->Mutex);
  this->Queued = nullptr;
  if (this->Running)
  {
    this->CancelRequested = true;
  }
}

//------------------------------------------------------------------------------
void BackgroundLighting::Stop()
{
  this->Cancel();
  std::unique_lock<std::mutex> lock(this->Mutex);
  if (this->Running || this->Queued)
  {
    ++WaitCount;
  }
  this->Changed.wait(lock, [this] { return !this->Running && !this->Queued; });
}

//------------------------------------------------------------------------------
void BackgroundLighting::Run(const Work& work, vtkAlgorithm* progressTo)
{
  this->Stop();
  ++WaitCount;
  this->CancelRequested = false;
  Job job(this, progressTo);
  work(job);
}

//------------------------------------------------------------------------------
bool BackgroundLighting::Take(Result& result)
{
  std::lock_guard<std::mutex> lock(this->Mutex);
  if (!this->HasLatest)
  {
    return false;
  }
  result = std::move(this->Latest);
  this->Latest = Result();
  this->HasLatest = false;
  return true;
}

//------------------------------------------------------------------------------
void BackgroundLighting::Discard()
{
  std::lock_guard<std::mutex> lock(this->Mutex);
  this->Latest = Result();
  this->HasLatest = false;
}

//------------------------------------------------------------------------------
bool BackgroundLighting::Busy() const
{
  std::lock_guard<std::mutex> lock(this->Mutex);
  return this->Running || this->Queued;
}

//------------------------------------------------------------------------------
bool BackgroundLighting::Ready() const
{
  std::lock_guard<std::mutex> lock(this->Mutex);
  return this->HasLatest;
}

//------------------------------------------------------------------------------
bool BackgroundLighting::AnyBusy()
{
  std::lock_guard<std::mutex> lock(RegistryMutex);
  const auto& registry = Registry();
  return std::any_of(
    registry.begin(), registry.end(), [](const BackgroundLighting* b) { return b->Busy(); });
}

bool BackgroundLighting::AnyReady()
{
  std::lock_guard<std::mutex> lock(RegistryMutex);
  const auto& registry = Registry();
  return std::any_of(
    registry.begin(), registry.end(), [](const BackgroundLighting* b) { return b->Ready(); });
}

unsigned int BackgroundLighting::Publications()
{
  return PublishedCount.load();
}

unsigned int BackgroundLighting::Waits()
{
  return WaitCount.load();
}

double BackgroundLighting::LeastProgress()
{
  std::lock_guard<std::mutex> lock(RegistryMutex);
  double least = 1.0;
  for (const BackgroundLighting* b : Registry())
  {
    if (b->Busy())
    {
      least = std::min(least, b->Progress());
    }
  }
  return least;
}

void BackgroundLighting::CancelAll()
{
  std::lock_guard<std::mutex> lock(RegistryMutex);
  for (BackgroundLighting* b : Registry())
  {
    b->Cancel();
  }
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkColorTransferFunction> JobCopies::Color(vtkColorTransferFunction* original)
{
  auto& c = this->ColorCopy;
  return Renewed(original, c.Original, c.Time, c.Owned, DeepCopyOf<vtkColorTransferFunction>);
}

vtkSmartPointer<vtkPiecewiseFunction> JobCopies::Opacity(vtkPiecewiseFunction* original)
{
  auto& c = this->OpacityCopy;
  return Renewed(original, c.Original, c.Time, c.Owned, DeepCopyOf<vtkPiecewiseFunction>);
}

vtkSmartPointer<vtkDataSet> JobCopies::Data(vtkDataSet* original)
{
  auto& c = this->DataCopy;
  return Renewed(original, c.Original, c.Time, c.Owned,
    [](vtkDataSet* d)
    {
      vtkSmartPointer<vtkDataSet> copy;
      copy.TakeReference(d->NewInstance());
      copy->ShallowCopy(d);
      return copy;
    });
}

//------------------------------------------------------------------------------
void LightingCosts::Record(const BackgroundLighting::Result& result)
{
  auto* data = vtkDataSet::SafeDownCast(result.Data);
  const double points = data ? static_cast<double>(data->GetNumberOfPoints()) : 0.0;
  this->SecondsPerPoint[result.Kind] = result.Seconds / std::max(points, 1.0);
}

//------------------------------------------------------------------------------
void ShownLighting::KeepFinal(
  const BackgroundLighting::Result& result, UpdateReport& report, double& seconds)
{
  if (result.Final)
  {
    this->LastFinal = result.Data;
    report = result.Report;
    seconds = result.Seconds;
    this->Costs.Record(result);
  }
}

//------------------------------------------------------------------------------
LightingCosts::Plan LightingCosts::Choose(int kind, double points) const
{
  auto measured = this->SecondsPerPoint.find(kind);
  if (measured == this->SecondsPerPoint.end())
  {
    measured = this->SecondsPerPoint.find(-1);
  }
  if (measured == this->SecondsPerPoint.end())
  {
    return points > CoarseFirstPoints ? Plan::CoarseFirst : Plan::Background;
  }
  const double expected = measured->second * points;
  if (expected <= NowSeconds)
  {
    return Plan::Now;
  }
  return expected > CoarseFirstSeconds ? Plan::CoarseFirst : Plan::Background;
}

}
