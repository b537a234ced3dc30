// sluice-play: a thin main over the runtime library (runtime/src/PlayCli.cpp).
#include "sluice/rt/PlayCli.h"

int main(int argc, char** argv) {
    return sluice::rt::runPlay(argc, argv);
}
