/**
 * @file ParallelSteps.h
 * @brief Dependent parallel loops run by one team of threads.
 *
 * A light sweep is a chain of parallel loops, each needing the one before: the rows of a
 * slice read the rays of the previous slice. One vtkSMPTools::For per loop costs whatever
 * the SMP backend needs to start its threads; VTK's STDThread backend starts a new pool of
 * threads at every call (~120 us for 2 threads measured on a 2-core VM), more than the work
 * of a small slice. ForSteps starts the threads once for a whole chain of loops (steps).
 *
 * Each thread of the team claims items of the current step (a few at a time, from a shared
 * counter) until none is left, then waits until every claimed item of the step is done
 * before it starts the next step. A thread only ever waits for items that running threads
 * have claimed, never for a thread that has not started, so the team cannot deadlock
 * whether the backend runs its threads concurrently or one after the other (the Sequential
 * backend, or STDThread called from inside another parallel loop: one thread does every
 * step). Work items must not call vtkSMPTools themselves: a backend that lets a waiting
 * thread take other tasks (TBB with nested loops) could give it one that waits for the item
 * it holds. An exception thrown by an item stops the team and is thrown again by ForSteps.
 */
#ifndef ParallelSteps_h
#define ParallelSteps_h

#include "VolIllumKernelsModule.h"

#include <functional>

namespace volillum
{

/// The work of one thread: items [begin, end) of step `step`.
using StepWork = std::function<void(int step, long long begin, long long end)>;

/**
 * Runs steps 0 .. steps - 1 in order; step s has items(s) items. Every item of step s is
 * done, and its writes are visible, before any item of step s + 1 starts, so items(s) and
 * the items of step s may read what earlier steps wrote. Each thread calls newWork once and
 * does all of its items with the StepWork returned (its scratch memory lives there). A step
 * with 1 item is done by one thread while the others wait: the place for serial work
 * between two parallel steps.
 */
VOLILLUMKERNELS_EXPORT void ForSteps(int steps, const std::function<long long(int step)>& items,
  const std::function<StepWork()>& newWork);

}

#endif
