#pragma once
// A mutex with priority inheritance: a thread holding it runs at the priority of the highest one waiting
// for it. The sound card's thread (real-time) takes the audio player's lock for every period; without
// inheritance, an ordinary thread preempted by the machine's load while it held the lock made the card
// wait behind that load and run dry. Usable with std::lock_guard and std::unique_lock.
#include <pthread.h>

namespace hmp::audio {

class PiMutex {
 public:
  PiMutex() {
    pthread_mutexattr_t attr;
    pthread_mutexattr_init(&attr);
    pthread_mutexattr_setprotocol(&attr, PTHREAD_PRIO_INHERIT);
    pthread_mutex_init(&mutex_, &attr);
    pthread_mutexattr_destroy(&attr);
  }
  ~PiMutex() { pthread_mutex_destroy(&mutex_); }
  PiMutex(const PiMutex&) = delete;
  PiMutex& operator=(const PiMutex&) = delete;
  void lock() { pthread_mutex_lock(&mutex_); }
  bool try_lock() { return pthread_mutex_trylock(&mutex_) == 0; }
  void unlock() { pthread_mutex_unlock(&mutex_); }

 private:
  pthread_mutex_t mutex_;
};

}  // namespace hmp::audio
