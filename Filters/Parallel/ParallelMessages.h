/**
 * @file ParallelMessages.h
 * The errors and warnings of every process of a parallel update, printed once by the first
 * process (ParaView shows a client only that process's messages).
 */
#ifndef ParallelMessages_h
#define ParallelMessages_h

#include "VolIllumParallelModule.h"

#include <mutex>
#include <string>
#include <vector>

class vtkAlgorithm;
class vtkMultiProcessController;
class vtkObject;

namespace volillum
{

/**
 * The errors and warnings a filter reports during one parallel update, printed once by the
 * first process. ParaView shows a client only the first server process's messages, so an
 * error of another process's piece (a missing array, a bad coordinate) left the client an
 * empty output without a word. While one of these lives, the filter's messages are collected
 * on every process (ErrorEvent and WarningEvent observers: nothing is printed there); its
 * destructor, collective (every process's update ends together: the filters stop at the
 * same collective decisions), gathers them to the first process, which prints each distinct
 * message once as the filter's, naming the processes that reported it ("Process 1 of 2:
 * ...", "Processes 0-2 of 3: ..."). Without a controller (a serial run) it does nothing.
 */
class VOLILLUMPARALLEL_EXPORT ParallelMessages
{
public:
  ParallelMessages(vtkMultiProcessController* controller, vtkAlgorithm* filter);
  ~ParallelMessages();
  ParallelMessages(const ParallelMessages&) = delete;
  ParallelMessages& operator=(const ParallelMessages&) = delete;

  struct Message
  {
    bool Error = true; // else a warning
    std::string Text;  // as printed, with the processes that reported it
  };
  /// What the first process prints, given each process's collected messages (`collected[p]`:
  /// per message 'E' or 'W', its text and a '\0'): each distinct message once, in the order
  /// of its first report.
  static std::vector<Message> Report(const std::vector<std::string>& collected);

private:
  void Collect(vtkObject* caller, unsigned long event, void* text);

  vtkMultiProcessController* Controller = nullptr;
  vtkAlgorithm* Filter = nullptr;
  unsigned long Observers[2] = { 0, 0 };
  std::mutex Mutex;      // a message may come from a worker thread
  std::string Collected; // per message: 'E' or 'W', its text and a '\0'
};

}

#endif
