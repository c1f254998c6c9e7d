#include "ParallelMessages.h"

#include "vtkAlgorithm.h"
#include "vtkCommand.h"
#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"

#include <algorithm>
#include <map>
#include <sstream>
#include <string>

namespace volillum
{

//------------------------------------------------------------------------------
ParallelMessages::ParallelMessages(vtkMultiProcessController* controller, vtkAlgorithm* filter)
  : Controller(controller)
  , Filter(filter)
{
  if (this->Controller)
  {
    this->Observers[0] =
      filter->AddObserver(vtkCommand::ErrorEvent, this, &ParallelMessages::Collect);
    this->Observers[1] =
      filter->AddObserver(vtkCommand::WarningEvent, this, &ParallelMessages::Collect);
  }
}

//------------------------------------------------------------------------------
void ParallelMessages::Collect(vtkObject* caller, unsigned long event, void* text)
{
  // vtkOutputWindowDisplayErrorText (and ...WarningText) sends "ERROR: In <file>, line <n>"
  // (or "Warning: In ...") on a line of its own, then the object's description, ": " and the
  // message, then blank lines: only the message is kept.
  std::string message = text ? static_cast<const char*>(text) : "";
  if (message.rfind("ERROR: In ", 0) == 0 || message.rfind("Warning: In ", 0) == 0)
  {
    const size_t line = message.find('\n');
    message.erase(0, line == std::string::npos ? message.size() : line + 1);
  }
  const std::string description = caller->GetObjectDescription() + ": ";
  if (message.rfind(description, 0) == 0)
  {
    message.erase(0, description.size());
  }
  message.erase(message.find_last_not_of(" \n") + 1);
  std::lock_guard<std::mutex> lock(this->Mutex);
  this->Collected += event == vtkCommand::ErrorEvent ? 'E' : 'W';
  this->Collected += message;
  this->Collected += '\0';
}

//------------------------------------------------------------------------------
ParallelMessages::~ParallelMessages()
{
  vtkMultiProcessController* controller = this->Controller;
  if (!controller)
  {
    return;
  }
  this->Filter->RemoveObserver(this->Observers[0]);
  this->Filter->RemoveObserver(this->Observers[1]);
  const int processes = controller->GetNumberOfProcesses();
  const bool first = controller->GetLocalProcessId() == 0;
  vtkIdType length = static_cast<vtkIdType>(this->Collected.size());
  std::vector<vtkIdType> lengths(first ? processes : 0), offsets(first ? processes : 0);
  controller->Gather(&length, lengths.data(), 1, 0);
  vtkIdType total = 0;
  for (int p = 0; first && p < processes; ++p)
  {
    offsets[p] = total;
    total += lengths[p];
  }
  // Every process takes part even with nothing to say (a zero length).
  std::vector<char> all(std::max<vtkIdType>(total, 1));
  char none = 0;
  controller->GatherV(this->Collected.empty() ? &none : &this->Collected[0], all.data(), length,
    lengths.data(), offsets.data(), 0);
  if (!first || total == 0)
  {
    return;
  }
  std::vector<std::string> collected(processes);
  for (int p = 0; p < processes; ++p)
  {
    collected[p].assign(all.data() + offsets[p], static_cast<size_t>(lengths[p]));
  }
  vtkAlgorithm* filter = this->Filter;
  for (const Message& message : Report(collected))
  {
    if (message.Error)
    {
      vtkErrorWithObjectMacro(filter, << message.Text);
    }
    else
    {
      vtkWarningWithObjectMacro(filter, << message.Text);
    }
  }
}

//------------------------------------------------------------------------------
std::vector<ParallelMessages::Message> ParallelMessages::Report(
  const std::vector<std::string>& collected)
{
  // Each distinct message (severity and text) with the processes that reported it.
  std::vector<std::pair<std::string, std::vector<int>>> distinct;
  for (int p = 0; p < static_cast<int>(collected.size()); ++p)
  {
    const std::string& messages = collected[p];
    for (size_t at = 0; at < messages.size();)
    {
      size_t end = messages.find('\0', at);
      end = end == std::string::npos ? messages.size() : end;
      const std::string message = messages.substr(at, end - at);
      at = end + 1;
      auto found = std::find_if(distinct.begin(), distinct.end(),
        [&](const std::pair<std::string, std::vector<int>>& d) { return d.first == message; });
      if (found == distinct.end())
      {
        distinct.emplace_back(message, std::vector<int>());
        found = distinct.end() - 1;
      }
      if (found->second.empty() || found->second.back() != p)
      {
        found->second.push_back(p);
      }
    }
  }
  std::vector<Message> report;
  for (const auto& d : distinct)
  {
    const std::vector<int>& who = d.second;
    std::ostringstream text;
    text << (who.size() == 1 ? "Process " : "Processes ");
    // Runs of consecutive processes as ranges: "0-2, 5".
    for (size_t i = 0; i < who.size();)
    {
      size_t j = i;
      while (j + 1 < who.size() && who[j + 1] == who[j] + 1)
      {
        ++j;
      }
      text << (i > 0 ? ", " : "") << who[i];
      if (j > i)
      {
        text << "-" << who[j];
      }
      i = j + 1;
    }
    text << " of " << collected.size() << ": " << d.first.substr(d.first.empty() ? 0 : 1);
    report.push_back({ d.first.empty() || d.first[0] != 'W', text.str() });
  }
  return report;
}

}
