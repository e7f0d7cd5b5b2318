#include "tools/work_precision/errors.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sinew::wp {

Errors compare(const Trajectory& run, const Trajectory& reference) {
  Errors e;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const size_t samples = std::min(run.times.size(), reference.times.size());
  e.comparable = samples > 0;
  for (size_t k = 0; k < samples && e.comparable; ++k)
    e.comparable = std::abs(run.times[k] - reference.times[k]) <= 1e-6 * std::max(1.0, reference.times[k]) &&
                   run.surface[k].size() == reference.surface[k].size();
  if (!e.comparable) {
    e.rms_distance = e.max_distance = e.energy_error = nan;
    return e;
  }
  double sum = 0, scale = 0;
  long count = 0;
  for (size_t k = 0; k < samples; ++k) {
    for (size_t i = 0; i < run.surface[k].size(); ++i) {
      const double d = (run.surface[k][i] - reference.surface[k][i]).norm();
      sum += d * d;
      e.max_distance = std::max(e.max_distance, d);
    }
    count += static_cast<long>(run.surface[k].size());
    e.energy_error = std::max(e.energy_error, std::abs(run.energy[k] - reference.energy[k]));
  }
  for (double energy : reference.energy) scale = std::max(scale, std::abs(energy - reference.energy.front()));
  e.rms_distance = count > 0 ? std::sqrt(sum / count) : 0;
  e.energy_error = scale > 0 ? e.energy_error / scale : nan;
  return e;
}

}  // namespace sinew::wp
