// sluice-bake: the offline collider baker. All logic lives in the sluice_bake library.
#include "sluice/bake/commands/Cli.h"

int main(int argc, char** argv) { return sluice::bake::runCli(argc, argv); }
