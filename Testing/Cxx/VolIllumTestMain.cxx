// main() of the GoogleTest programs: the SMP backend is chosen here, once, as an
// application does (Debian's VTK starts with the Sequential one); VTK_SMP_BACKEND_IN_USE
// still overrides it.
#include "vtkSMPTools.h"

#include <gtest/gtest.h>

#include <cstdlib>

int main(int argc, char** argv)
{
  if (!std::getenv("VTK_SMP_BACKEND_IN_USE"))
  {
    vtkSMPTools::SetBackend("STDThread");
  }
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
