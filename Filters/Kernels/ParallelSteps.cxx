#include "ParallelSteps.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>

namespace volillum
{

void ForSteps(
  int steps, const std::function<long long(int)>& items, const std::function<StepWork()>& newWork)
{
  if (steps <= 0)
  {
    return;
  }
  const int threads = std::max(1, vtkSMPTools::GetEstimatedNumberOfThreads());
  // Per step: items claimed (may overshoot the count) and items done.
  const auto claimed = std::make_unique<std::atomic<long long>[]>(steps);
  const auto done = std::make_unique<std::atomic<long long>[]>(steps);
  for (int s = 0; s < steps; ++s)
  {
    claimed[s].store(0, std::memory_order_relaxed);
    done[s].store(0, std::memory_order_relaxed);
  }
  // A thread whose work throws stops the team (the others would wait for its items forever);
  // the first exception is thrown again here.
  std::atomic<bool> failed(false);
  std::exception_ptr error;
  std::mutex errorMutex;
  // One call per thread; a backend that runs the calls one after the other (or all at once
  // in one call) gives the first call every item.
  vtkSMPTools::For(0, threads, 1,
    [&](int, int)
    {
      try
      {
        StepWork work = newWork();
        for (int s = 0; s < steps && !failed.load(std::memory_order_relaxed); ++s)
        {
          const long long count = items(s);
          // A few claims per thread balance uneven items without contention on the counter.
          const long long grain = std::max(1LL, count / (16LL * threads));
          while (!failed.load(std::memory_order_relaxed))
          {
            const long long begin = claimed[s].fetch_add(grain, std::memory_order_relaxed);
            if (begin >= count)
            {
              break;
            }
            const long long end = std::min(count, begin + grain);
            work(s, begin, end);
            done[s].fetch_add(end - begin, std::memory_order_release);
          }
          while (done[s].load(std::memory_order_acquire) < count &&
            !failed.load(std::memory_order_acquire))
          {
            std::this_thread::yield();
          }
        }
      }
      catch (...)
      {
        const std::lock_guard<std::mutex> lock(errorMutex);
        if (!error)
        {
          error = std::current_exception();
        }
        failed.store(true, std::memory_order_release);
      }
    });
  if (error)
  {
    std::rethrow_exception(error);
  }
}

}
