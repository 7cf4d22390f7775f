#include "live_temporaries.h"

#include <limits.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstring>

#include "imuconv/pipeline/output_file.h"

namespace imuconv::pipeline {
namespace live_temporaries {
namespace {

// A fixed table, no allocation and no lock: the handler may run on any thread at any moment and
// may only use async-signal-safe calls (unlink, raise) and lock-free atomics. A slot is
// reserved (Filling) while its path is copied in, so the handler never reads half a path.
constexpr int kSlots = 16;  // one output per command today; room for a library user with a few
enum SlotState : int { kFree, kFilling, kLive };
struct Slot {
  std::atomic<int> state{kFree};
  char path[PATH_MAX];
};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler needs lock-free atomics");
Slot g_slots[kSlots];

}  // namespace

int Remember(const std::string& path) {
  if (path.size() >= PATH_MAX) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (g_slots[i].state.compare_exchange_strong(expected, kFilling)) {
      std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
      g_slots[i].state.store(kLive);
      return i;
    }
  }
  return -1;
}

void Forget(int slot) {
  if (slot >= 0) g_slots[slot].state.store(kFree);
}

namespace {

// Installed with SA_RESETHAND, so the disposition is the default again when this runs; the
// signal is blocked while it runs, so raise() leaves it pending and it is delivered, with its
// default action, as the handler returns.
void RemoveTemporariesAndDie(int sig) {
  for (auto& s : g_slots)
    if (s.state.load() == kLive) ::unlink(s.path);
  ::raise(sig);
}

}  // namespace
}  // namespace live_temporaries

void RemoveTemporariesOnSignal() {
  const int signals[] = {SIGINT, SIGTERM, SIGHUP, SIGPIPE};
  struct sigaction sa {};
  sa.sa_handler = live_temporaries::RemoveTemporariesAndDie;
  sigemptyset(&sa.sa_mask);
  for (int s : signals) sigaddset(&sa.sa_mask, s);  // one cleanup at a time
  sa.sa_flags = SA_RESETHAND;
  for (int s : signals) {
    struct sigaction old {};
    if (::sigaction(s, nullptr, &old) != 0) continue;
    if (!(old.sa_flags & SA_SIGINFO) && old.sa_handler == SIG_IGN)
      continue;  // nohup: keep ignoring it
    ::sigaction(s, &sa, nullptr);
  }
}

}  // namespace imuconv::pipeline
