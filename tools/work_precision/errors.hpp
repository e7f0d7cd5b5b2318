#pragma once
// Errors of a run against its reference, on the states at the common sample times.
#include "tools/work_precision/run.hpp"

namespace sinew::wp {

struct Errors {
  bool comparable = false;  // same sample times and surfaces (else the values are NaN)
  double rms_distance = 0;  // m: sqrt of the mean over samples and surface vertices of |x - x_ref|^2
  double max_distance = 0;  // m: the largest |x - x_ref| of any vertex at any sample
  // max over samples of |E - E_ref|, relative to the energy the reference exchanges
  // (max over samples of |E_ref - E_ref(0)|): 1 means an error as large as the whole change.
  double energy_error = 0;
};

// A run that stopped early is compared over the samples it reached.
Errors compare(const Trajectory& run, const Trajectory& reference);

}  // namespace sinew::wp
