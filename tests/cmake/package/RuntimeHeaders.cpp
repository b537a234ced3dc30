// Compiles the installed runtime and GPU headers as a game would include them.
#include "shared/GpuSelfTest.h"
#include "sluice/gpu/Program.h"
#include "sluice/rt/sim/SceneSetup.h"
