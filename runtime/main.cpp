// sluice-play: a thin main over the runtime library (runtime/src/play/PlayCli.cpp).
#include "sluice/rt/play/PlayCli.h"

int main(int argc, char** argv) {
    return sluice::rt::runPlay(argc, argv);
}
