#include "core/run/signals.hpp"

#include <signal.h>

#include <csignal>

namespace harness {

namespace {
volatile std::sig_atomic_t g_signal = 0;
extern "C" void on_stop_signal(int sig) { g_signal = sig; }
}  // namespace

struct StopSignals::Saved {
  struct sigaction old_int {}, old_term {};
};

StopSignals::StopSignals() : saved_(std::make_unique<Saved>()) {
  g_signal = 0;
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;
  sigaction(SIGINT, &sa, &saved_->old_int);
  sigaction(SIGTERM, &sa, &saved_->old_term);
}

StopSignals::~StopSignals() {
  sigaction(SIGINT, &saved_->old_int, nullptr);
  sigaction(SIGTERM, &saved_->old_term, nullptr);
}

int stop_signal() { return g_signal; }

}  // namespace harness
