// The signal flag: written by the handler, read between steps.
#include "play/Interrupt.h"

#include <csignal>

#include <unistd.h>

namespace sluice::rt {
namespace {

volatile std::sig_atomic_t g_signal = 0;

extern "C" void onSignal(int signal) {
    if (g_signal == 0)
        g_signal = signal;
    // What a user sees at once, before the current step ends (write is async-signal-safe).
    constexpr char kNote[] = "\nsluice-play: interrupted: finishing the current step and "
                             "writing the outputs (again to quit at once)\n";
    const ssize_t ignored = ::write(STDERR_FILENO, kNote, sizeof kNote - 1);
    (void)ignored;
}

} // namespace

InterruptGuard::InterruptGuard() {
    g_signal = 0;
    struct sigaction action {};
    action.sa_handler = onSignal;
    sigemptyset(&action.sa_mask);
    // SA_RESETHAND: the second signal takes the default action and ends the process.
    action.sa_flags = SA_RESETHAND | SA_RESTART;
    ::sigaction(SIGINT, &action, &m_savedInterrupt);
    ::sigaction(SIGTERM, &action, &m_savedTerminate);
}

InterruptGuard::~InterruptGuard() {
    ::sigaction(SIGINT, &m_savedInterrupt, nullptr);
    ::sigaction(SIGTERM, &m_savedTerminate, nullptr);
}

int InterruptGuard::requested() {
    return g_signal;
}

int InterruptGuard::exitCode() {
    return 128 + g_signal;
}

const char* InterruptGuard::signalName() {
    return g_signal == SIGTERM ? "SIGTERM" : "SIGINT";
}

} // namespace sluice::rt
