#pragma once
// CPU time used by the calling thread: the clock of cost measurements, which on a shared machine would
// otherwise count the time other processes hold the core.
namespace hmp {

double thread_cpu_seconds();

}  // namespace hmp
