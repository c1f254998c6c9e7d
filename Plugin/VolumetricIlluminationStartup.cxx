// Runs once when ParaView loads the plugin, in every process that loads it (the client,
// pvserver, pvbatch, pvpython): Debian's ParaView starts with VTK's Sequential SMP backend,
// which would light a volume on one core. Unless the user chose a backend with
// VTK_SMP_BACKEND_IN_USE, the plugin switches to STDThread here, once; the filters never
// change it. Programs that use the filters without the plugin choose a backend in their
// main() (volillum-render, the tests and the benchmarks do).
#include "IlluminationFilterSupport.h"

namespace
{
const bool ThreadedBackendChosen = []
{
  volillum::UseThreadedBackend();
  return true;
}();
}
