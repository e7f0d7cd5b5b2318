#include "engine/materials/arap.hpp"

namespace sinew {

Arap::Arap(const MaterialParameters& params) : Corotational(lame_parameters(params).mu, 0.0) {}

}  // namespace sinew
