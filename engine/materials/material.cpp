#include "engine/materials/material.hpp"

#include <stdexcept>

#include "engine/materials/arap.hpp"
#include "engine/materials/arruda_boyce.hpp"
#include "engine/materials/corotational.hpp"
#include "engine/materials/fung.hpp"
#include "engine/materials/neo_hookean.hpp"
#include "engine/materials/stable_neo_hookean.hpp"
#include "engine/materials/stvk.hpp"

namespace sinew {

LameParameters lame_parameters(const MaterialParameters& params) {
  const double E = params.young, nu = params.poisson;
  if (!(E > 0) || !(nu > -1 && nu < 0.5))
    throw std::invalid_argument("material: need young > 0 and -1 < poisson < 0.5");
  return {E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu))};
}

const std::vector<std::string>& material_names() {
  static const std::vector<std::string> names = {"stable_neo_hookean", "neo_hookean", "corotational",
                                                 "arap", "stvk", "fung", "arruda_boyce"};
  return names;
}

std::unique_ptr<Material> make_material(const std::string& name, const MaterialParameters& params) {
  if (name == "stable_neo_hookean") return std::make_unique<StableNeoHookean>(params);
  if (name == "neo_hookean") return std::make_unique<NeoHookean>(params);
  if (name == "corotational") return std::make_unique<Corotational>(params);
  if (name == "arap") return std::make_unique<Arap>(params);
  if (name == "stvk") return std::make_unique<Stvk>(params);
  if (name == "fung") return std::make_unique<Fung>(params);
  if (name == "arruda_boyce") return std::make_unique<ArrudaBoyce>(params);
  std::string message = "unknown material '" + name + "'; known:";
  for (const std::string& known : material_names()) message += " " + known;
  throw std::invalid_argument(message);
}

}  // namespace sinew
