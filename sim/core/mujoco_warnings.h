// MuJoCo's warning hook is one process-wide pointer, and the program's
// hook need not be thread-safe. While an instance of
// SerialisedMujocoWarnings lives (create it before the threads start),
// calls to the hook are serialised. Used by FanOut (sim/core/fan_out.h).
#pragma once

#include <mujoco/mujoco.h>

#include <mutex>

namespace ipmc {

class SerialisedMujocoWarnings {
 public:
  SerialisedMujocoWarnings() {
    std::lock_guard<std::mutex> lock(Mutex());
    if (Users()++ == 0) {
      Previous() = mju_user_warning;
      if (Previous() != nullptr) mju_user_warning = Forward;
    }
  }
  ~SerialisedMujocoWarnings() {
    std::lock_guard<std::mutex> lock(Mutex());
    if (--Users() == 0 && Previous() != nullptr) {
      mju_user_warning = Previous();
      Previous() = nullptr;
    }
  }
  SerialisedMujocoWarnings(const SerialisedMujocoWarnings&) = delete;
  SerialisedMujocoWarnings& operator=(const SerialisedMujocoWarnings&) = delete;

 private:
  using Hook = void (*)(const char*);
  static std::mutex& Mutex() {
    static std::mutex mutex;
    return mutex;
  }
  static int& Users() {
    static int users = 0;
    return users;
  }
  static Hook& Previous() {
    static Hook previous = nullptr;
    return previous;
  }
  static void Forward(const char* message) {
    std::lock_guard<std::mutex> lock(Mutex());
    if (Previous() != nullptr) Previous()(message);
  }
};

}  // namespace ipmc
