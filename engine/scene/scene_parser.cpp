// Scene file parser: JSON text -> SceneDesc, validating every key. Schema: docs/scenes.md.
//
// Reading goes through two small helpers. `Node` is one JSON value plus its path in the
// file ("bodies[0].material.E"); its typed getters validate and throw InputError naming
// that path. `Object` is a Node known to be a JSON object whose keys have been checked
// against the keys the schema allows there.
#include <algorithm>
#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <utility>
#include <string_view>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "engine/core/error.hpp"
#include "engine/scene/scene.hpp"

namespace sinew {

bool RegionDesc::contains(const Vec3& p) const {
  if (kind == Kind::Box) return (p.array() >= a.array()).all() && (p.array() <= b.array()).all();
  return (p - a).dot(b) <= 0;
}

const std::vector<std::string>& material_model_names() {
  static const std::vector<std::string> names = {
      "corotational", "stable_neo_hookean", "neo_hookean", "corotational_hyperelastic",
      "arap", "stvk", "fung", "arruda_boyce"};
  return names;
}

int SceneDesc::steps_per_frame() const {
  const double steps = std::round(1.0 / (fps * h));
  return static_cast<int>(std::clamp(steps, 1.0, static_cast<double>(INT_MAX)));
}

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using KeyList = std::vector<std::string>;

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

std::string index_path(const std::string& path, std::size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

std::string number_text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// A value as it appears in a message: its JSON text, shortened if long.
std::string describe(const json& v) {
  if (v.is_number_float() && !std::isfinite(v.get<double>())) return "a non-finite number";
  std::string s = v.dump();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

// "\"a\", \"b\", \"c\""
std::string quoted_list(const KeyList& items, char quote) {
  std::string s;
  for (const std::string& item : items) s += (s.empty() ? "" : ", ") + (quote + item + quote);
  return s;
}

// Accepted interval of a number; each end open, closed or absent (infinite).
struct Range {
  double lo = -kInf, hi = kInf;
  bool lo_open = false, hi_open = false;

  bool contains(double v) const {
    return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  // " > 0", " in [0, 0.5)", or "" when unbounded; appended to "a number" in messages.
  std::string text() const {
    const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
    if (has_lo && has_hi)
      return std::string(" in ") + (lo_open ? "(" : "[") + number_text(lo) + ", " +
             number_text(hi) + (hi_open ? ")" : "]");
    if (has_lo) return (lo_open ? " > " : " >= ") + number_text(lo);
    if (has_hi) return (hi_open ? " < " : " <= ") + number_text(hi);
    return "";
  }
};

const Range kAny{};
const Range kPositive{0, kInf, true, false};
const Range kNonNegative{0, kInf, false, false};
const Range kPoisson{0, 0.5, false, true};
const Range kFraction{0, 1, false, true};

// Edit distance with adjacent transpositions (optimal string alignment), case-insensitive.
std::size_t edit_distance(std::string_view a, std::string_view b) {
  const auto same = [](unsigned char x, unsigned char y) {
    return std::tolower(x) == std::tolower(y);
  };
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1,
                          d[i - 1][j - 1] + (same(a[i - 1], b[j - 1]) ? 0 : 1)});
      if (i > 1 && j > 1 && same(a[i - 1], b[j - 2]) && same(a[i - 2], b[j - 1]))
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[a.size()][b.size()];
}

// The known key closest to `unknown`, if it is close enough to be a plausible typo.
std::optional<std::string> closest_key(const std::string& unknown, const KeyList& known) {
  std::optional<std::string> best;
  std::size_t best_distance = SIZE_MAX;
  for (const std::string& key : known) {
    const std::size_t d = edit_distance(unknown, key);
    const bool close = d <= std::max<std::size_t>(1, key.size() / 3) && d < unknown.size();
    if (close && d < best_distance) {
      best = key;
      best_distance = d;
    }
  }
  return best;
}

Mat3 rotation_from_euler_deg(const Vec3& degrees) {
  const Vec3 r = degrees * (std::numbers::pi / 180.0);
  using Eigen::AngleAxisd;
  return (AngleAxisd(r.z(), Vec3::UnitZ()) * AngleAxisd(r.y(), Vec3::UnitY()) *
          AngleAxisd(r.x(), Vec3::UnitX()))
      .toRotationMatrix();
}

struct Source {
  std::string name;     // file name used in messages
  fs::path base_dir;    // mesh paths are relative to this
};

// One JSON value and where it is in the file.
class Node {
 public:
  Node(const json& value, std::string path, const Source& source)
      : value_(&value), path_(std::move(path)), source_(&source) {}

  const json& value() const { return *value_; }
  const std::string& path() const { return path_; }
  const Source& source() const { return *source_; }
  Node child(const std::string& key) const {
    return Node(value_->at(key), join(path_, key), *source_);
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(source_->name + ": " + (path_.empty() ? "(root)" : path_) + ": " + what);
  }
  [[noreturn]] void expected(const std::string& what) const {
    fail("expected " + what + ", got " + describe(*value_));
  }

  double number(const Range& range = kAny) const {
    if (!value_->is_number()) expected("a number" + range.text());
    const double v = value_->get<double>();
    if (!std::isfinite(v) || !range.contains(v)) expected("a number" + range.text());
    return v;
  }

  // Integral numbers only (120 or 120.0, not 120.5).
  int integer(const Range& range) const {
    const std::string what = "an integer" + range.text();
    if (!value_->is_number()) expected(what);
    const double v = value_->get<double>();
    if (!std::isfinite(v) || v != std::floor(v) || std::abs(v) > INT_MAX || !range.contains(v))
      expected(what);
    return static_cast<int>(v);
  }

  std::string string() const {
    if (!value_->is_string()) expected("a string");
    return value_->get<std::string>();
  }

  std::string choice(const KeyList& allowed) const {
    const std::string what = "one of " + quoted_list(allowed, '"');
    if (!value_->is_string()) expected(what);
    const std::string s = value_->get<std::string>();
    if (std::find(allowed.begin(), allowed.end(), s) == allowed.end()) expected(what);
    return s;
  }

  Vec3 vec3(const Range& range = kAny) const {
    const json& v = *value_;
    const auto valid = [&](const json& c) {
      return c.is_number() && std::isfinite(c.get<double>()) && range.contains(c.get<double>());
    };
    if (!v.is_array() || v.size() != 3 || !std::all_of(v.begin(), v.end(), valid))
      expected("an array of 3 numbers" + range.text());
    return Vec3(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
  }

  // A non-zero vector, returned normalised.
  Vec3 direction() const {
    const Vec3 v = vec3();
    if (!(v.norm() > 0)) expected("a non-zero array of 3 numbers");
    return v.normalized();
  }

  std::vector<Node> elements(bool non_empty) const {
    const char* what = non_empty ? "a non-empty array" : "an array";
    if (!value_->is_array() || (non_empty && value_->empty())) expected(what);
    std::vector<Node> out;
    for (std::size_t i = 0; i < value_->size(); ++i)
      out.emplace_back((*value_)[i], index_path(path_, i), *source_);
    return out;
  }

 private:
  const json* value_;
  std::string path_;
  const Source* source_;
};

// A JSON object. Optional getters leave `out` unchanged when the key is absent.
class Object {
 public:
  explicit Object(const Node& node) : node_(node) {
    if (!node.value().is_object()) node.expected("an object");
  }
  Object(const Node& node, const KeyList& known) : Object(node) { check_keys(known); }

  // Every key must be in `known`; otherwise name it and suggest the closest known key.
  void check_keys(const KeyList& known) const {
    for (const auto& item : node_.value().items()) {
      const std::string& key = item.key();
      if (std::find(known.begin(), known.end(), key) != known.end()) continue;
      const std::optional<std::string> suggestion = closest_key(key, known);
      node_.child(key).fail("unknown key '" + key + "' " +
                            (suggestion ? "(did you mean '" + *suggestion + "'?)"
                                        : "(expected one of: " + quoted_list(known, '\'') + ")"));
    }
  }

  const Node& node() const { return node_; }
  bool has(const std::string& key) const { return node_.value().contains(key); }
  std::optional<Node> get(const std::string& key) const {
    if (!has(key)) return std::nullopt;
    return node_.child(key);
  }
  Node require(const std::string& key) const {
    if (!has(key)) node_.fail("missing required key '" + key + "'");
    return node_.child(key);
  }

  void number(const std::string& key, double& out, const Range& range = kAny) const {
    if (auto n = get(key)) out = n->number(range);
  }
  void integer(const std::string& key, int& out, const Range& range) const {
    if (auto n = get(key)) out = n->integer(range);
  }
  void string(const std::string& key, std::string& out) const {
    if (auto n = get(key)) out = n->string();
  }
  void choice(const std::string& key, std::string& out, const KeyList& allowed) const {
    if (auto n = get(key)) out = n->choice(allowed);
  }
  void vec3(const std::string& key, Vec3& out, const Range& range = kAny) const {
    if (auto n = get(key)) out = n->vec3(range);
  }

  // Exactly one of keys `a` and `b` must be present; returns true for `a`.
  bool one_of(const std::string& a, const std::string& b) const {
    if (has(a) != has(b)) return has(a);
    node_.fail("expected exactly one of '" + a + "' or '" + b + "', got " +
               (has(a) ? "both" : "neither"));
  }

 private:
  Node node_;
};

// ---- Schema -------------------------------------------------------------------------

RegionDesc parse_box(const Node& node) {
  const Object o(node, {"min", "max"});
  RegionDesc r;
  r.kind = RegionDesc::Kind::Box;
  r.a = o.require("min").vec3();
  r.b = o.require("max").vec3();
  if (!(r.a.array() < r.b.array()).all())
    node.fail("expected min < max in every component, got min " + describe(node.value()["min"]) +
              ", max " + describe(node.value()["max"]));
  return r;
}

RegionDesc parse_half_space(const Node& node) {
  const Object o(node, {"point", "normal"});
  RegionDesc r;
  r.kind = RegionDesc::Kind::HalfSpace;
  r.a = o.require("point").vec3();
  r.b = o.require("normal").direction();
  return r;
}

// `o` holds exactly one of "box" / "half_space" (its keys are already checked).
RegionDesc parse_region(const Object& o) {
  return o.one_of("box", "half_space") ? parse_box(o.require("box"))
                                       : parse_half_space(o.require("half_space"));
}

constexpr PrimitiveKind kAllKinds[] = {PrimitiveKind::Box, PrimitiveKind::Sphere,
                                       PrimitiveKind::Cylinder, PrimitiveKind::Capsule,
                                       PrimitiveKind::Ellipsoid};

PrimitiveKind parse_kind(const Node& node) {
  KeyList names;
  for (PrimitiveKind k : kAllKinds) names.emplace_back(primitive_kind_name(k));
  bool ok = false;
  const PrimitiveKind kind = parse_primitive_kind(node.choice(names), ok);
  if (!ok) node.expected("one of " + quoted_list(names, '"'));
  return kind;
}

KeyList primitive_keys(PrimitiveKind kind) {
  KeyList keys{"type", "center", "rotation_deg"};
  switch (kind) {
    case PrimitiveKind::Box: keys.push_back("half_extents"); break;
    case PrimitiveKind::Sphere: keys.push_back("radius"); break;
    case PrimitiveKind::Cylinder:
    case PrimitiveKind::Capsule: keys.insert(keys.end(), {"radius", "length"}); break;
    case PrimitiveKind::Ellipsoid: keys.push_back("semi_axes"); break;
  }
  return keys;
}

Primitive parse_primitive(const Node& node) {
  const Object o(node);
  Primitive p;
  p.kind = parse_kind(o.require("type"));
  o.check_keys(primitive_keys(p.kind));
  switch (p.kind) {
    case PrimitiveKind::Box: p.size = o.require("half_extents").vec3(kPositive); break;
    case PrimitiveKind::Sphere:
      p.size = Vec3::Constant(o.require("radius").number(kPositive));
      break;
    case PrimitiveKind::Cylinder:
    case PrimitiveKind::Capsule: {
      // "length" is the axis segment's full length (cylinder: end to end; capsule: between
      // the cap centres); Primitive stores half of it in y.
      const double radius = o.require("radius").number(kPositive);
      const Range length_range = p.kind == PrimitiveKind::Cylinder ? kPositive : kNonNegative;
      const double length = o.require("length").number(length_range);
      p.size = Vec3(radius, 0.5 * length, radius);
      break;
    }
    case PrimitiveKind::Ellipsoid: p.size = o.require("semi_axes").vec3(kPositive); break;
  }
  o.vec3("center", p.center);
  if (auto r = o.get("rotation_deg")) p.rotation = rotation_from_euler_deg(r->vec3());
  return p;
}

// Absolute, normalised path of an existing, readable mesh file.
std::string resolve_mesh(const Node& node, bool tetgen_base = false) {
  const std::string given = node.string();
  if (given.empty()) node.expected("a non-empty file path");
  fs::path p(given);
  if (p.is_relative()) p = node.source().base_dir / p;
  std::error_code ec;
  const fs::path resolved = fs::absolute(p, ec).lexically_normal();
  const auto fail = [&](const std::string& problem) {
    node.fail("mesh file '" + given + "' " + problem + " (resolved to '" + resolved.string() +
              "')");
  };
  // A TetGen mesh may be named by its base name (the readers add .node and .ele).
  if (tetgen_base && !fs::exists(resolved, ec) && fs::is_regular_file(resolved.string() + ".node", ec))
    return resolved.string();
  if (!fs::exists(resolved, ec)) fail("not found");
  if (!fs::is_regular_file(resolved, ec)) fail("is not a regular file");
  if (!std::ifstream(resolved)) fail("cannot be read");
  return resolved.string();
}

void parse_transform(const Object& o, BodyDesc& body) {
  o.number("scale", body.scale, kPositive);
  if (auto r = o.get("rotation_deg")) body.rotate = rotation_from_euler_deg(r->vec3());
  o.vec3("translate", body.translate);
}

bool is_invariant_model(const std::string& model) {
  return model == "stable_neo_hookean" || model == "neo_hookean" || model == "fung" || model == "arruda_boyce";
}

MaterialDesc parse_material(const Object& o) {
  MaterialDesc m;
  o.choice("model", m.model, material_model_names());
  m.E = o.require("E").number(kPositive);
  m.nu = o.require("nu").number(kPoisson);
  m.rho = o.require("rho").number(kPositive);
  if (o.has("fung_c") && m.model != "fung") o.require("fung_c").fail("only allowed with model \"fung\"");
  if (o.has("arruda_boyce_n") && m.model != "arruda_boyce")
    o.require("arruda_boyce_n").fail("only allowed with model \"arruda_boyce\"");
  o.number("fung_c", m.fung_c, kPositive);
  o.number("arruda_boyce_n", m.arruda_boyce_n, Range{1, kInf, true, false});
  std::string volume_term = "per_point";
  o.choice("volume_term", volume_term, {"per_point", "mean_dilatation"});
  m.mean_dilatation = volume_term == "mean_dilatation";
  if (m.mean_dilatation && !is_invariant_model(m.model))
    o.require("volume_term").fail("\"mean_dilatation\" needs a model of the form f(Ic) + g(J): "
                                  "\"stable_neo_hookean\", \"neo_hookean\", \"fung\" or \"arruda_boyce\"");
  return m;
}

// A limit per axis: one number for all three, or an array of 3 whose entries are numbers
// or null (that axis is free).
Vec3 parse_axis_limits(const Node& n, double free_value, const Range& range) {
  if (n.value().is_number()) return Vec3::Constant(n.number(range));
  const auto valid = [&](const json& c) {
    return c.is_null() || (c.is_number() && std::isfinite(c.get<double>()) && range.contains(c.get<double>()));
  };
  if (!n.value().is_array() || n.value().size() != 3 || !std::all_of(n.value().begin(), n.value().end(), valid))
    n.expected("a number" + range.text() + " or an array of 3 such numbers or null (no limit)");
  Vec3 out;
  for (int j = 0; j < 3; ++j) out[j] = n.value()[j].is_null() ? free_value : n.value()[j].get<double>();
  return out;
}

StrainLimitDesc parse_strain_limit(const Object& o) {
  StrainLimitDesc d;
  d.enabled = true;
  o.choice("mode", d.mode, {"hyperbolic", "orthogonal", "linear", "isotropic"});
  o.choice("pair_cuts", d.pair_cuts, {"on", "off"});
  if (!o.has("smin") && !o.has("smax")) o.node().fail("expected 'smin', 'smax' or both");
  if (auto n = o.get("smin")) d.smin = parse_axis_limits(*n, 0.0, Range{0, 1, false, false});
  if (auto n = o.get("smax")) d.smax = parse_axis_limits(*n, kInf, Range{1, kInf, false, true});
  if (d.mode == "isotropic" && (d.smin.minCoeff() != d.smin.maxCoeff() || d.smax.minCoeff() != d.smax.maxCoeff()))
    o.node().fail("mode \"isotropic\" takes one smin and one smax for all axes");
  if (auto r = o.get("frame_deg")) d.frame = rotation_from_euler_deg(r->vec3());
  if (auto regions = o.get("frame_regions")) {
    for (const Node& n : regions->elements(false)) {
      const Object r(n, {"box", "half_space", "frame_deg"});
      d.frame_regions.push_back({parse_region(r), rotation_from_euler_deg(r.require("frame_deg").vec3())});
    }
  }
  return d;
}

EnergyLimitDesc parse_energy_limit(const Object& o) {
  EnergyLimitDesc e;
  e.enabled = true;
  e.Umax = o.require("Umax").number(kPositive);
  o.choice("jacobian", e.jacobian, {"exact", "warped"});
  if (auto regions = o.get("regions")) {
    for (const Node& n : regions->elements(false)) {
      const Object r(n, {"box", "half_space", "Umax"});
      e.regions.push_back({parse_region(r), r.require("Umax").number(kPositive)});
    }
  }
  return e;
}

const KeyList kBodyKeys = {"name",     "shape",   "mesh",  "tet_mesh", "elements", "transform",
                           "cell_size", "surface_resolution", "material", "damping", "fixed",
                           "velocity", "energy_limit", "strain_limit", "loads", "driven"};

// Exactly one of the geometry keys.
std::string geometry_key(const Object& o) {
  const KeyList keys = {"shape", "mesh", "tet_mesh"};
  KeyList present;
  for (const std::string& k : keys)
    if (o.has(k)) present.push_back(k);
  if (present.size() != 1)
    o.node().fail("expected exactly one of 'shape', 'mesh' or 'tet_mesh', got " +
                  (present.empty() ? std::string("none") : quoted_list(present, '\'')));
  return present[0];
}

BodyDesc parse_body(const Node& node, std::size_t index) {
  const Object o(node, kBodyKeys);
  BodyDesc b;
  b.json_path = node.path();
  b.name = "body" + std::to_string(index);
  o.string("name", b.name);
  if (b.name.empty()) o.require("name").expected("a non-empty string");

  const std::string geometry = geometry_key(o);
  if (geometry == "shape") {
    for (const Node& n : o.require("shape").elements(true))
      b.shape.parts.push_back(parse_primitive(n));
  } else {
    (geometry == "mesh" ? b.mesh_path : b.tet_mesh_path) = resolve_mesh(o.require(geometry), geometry == "tet_mesh");
    if (o.has("surface_resolution"))
      o.require("surface_resolution")
          .fail("only allowed with 'shape' (a mesh body's surface is its mesh)");
  }
  if (auto t = o.get("transform"))
    parse_transform(Object(*t, {"scale", "rotation_deg", "translate"}), b);
  o.choice("elements", b.elements, {"hex", "tet"});
  if (geometry == "tet_mesh") {
    if (o.has("elements") && b.elements != "tet") o.require("elements").fail("a tet_mesh body has \"tet\" elements");
    if (o.has("cell_size")) o.require("cell_size").fail("not used by a tet_mesh body (its mesh is the simulation mesh)");
    b.elements = "tet";
  } else {
    b.cell_size = o.require("cell_size").number(kPositive);
  }
  o.number("surface_resolution", b.surface_resolution, kNonNegative);
  b.material = parse_material(
      Object(o.require("material"), {"model", "E", "nu", "rho", "fung_c", "arruda_boyce_n", "volume_term"}));
  if (b.material.mean_dilatation && b.elements != "hex")
    o.require("material").child("volume_term").fail(
        "\"mean_dilatation\" is for hex elements (a tet has one point: its J is already the mean)");
  if (auto d = o.get("damping")) {
    const Object damping(*d, {"mass", "stiffness"});
    damping.number("mass", b.damping_mass, kNonNegative);
    damping.number("stiffness", b.damping_stiffness, kNonNegative);
  }
  if (b.material.hyperelastic() && b.damping_stiffness > 0)
    o.require("damping").child("stiffness").fail(
        "stiffness damping is only for the \"corotational\" model (its stiffness matrix is constant over a step); "
        "use mass damping with model \"" + b.material.model + "\"");
  if (auto f = o.get("fixed")) {
    for (const Node& n : f->elements(false))
      b.fixed.push_back(parse_region(Object(n, {"box", "half_space"})));
  }
  o.vec3("velocity", b.velocity);
  if (auto e = o.get("energy_limit"))
    b.energy_limit = parse_energy_limit(Object(*e, {"Umax", "jacobian", "regions"}));
  if (auto loads = o.get("loads")) {
    for (const Node& n : loads->elements(false)) {
      const Object l(n, {"box", "half_space", "force", "ramp_time"});
      LoadDesc load;
      load.region = parse_region(l);
      load.force = l.require("force").vec3();
      l.number("ramp_time", load.ramp_time, kNonNegative);
      b.loads.push_back(load);
    }
  }
  if (auto driven = o.get("driven")) {
    if (!b.material.hyperelastic())
      driven->fail("driven nodes need a hyperelastic material model (e.g. \"stable_neo_hookean\" or "
                   "\"corotational_hyperelastic\"): the linear \"corotational\" step has no coupling to "
                   "prescribed nodes");
    for (const Node& n : driven->elements(false)) {
      const Object d(n, {"box", "half_space", "rotate"});
      DrivenDesc desc;
      desc.region = parse_region(d);
      const Object r(d.require("rotate"), {"axis", "pivot", "degrees", "duration"});
      desc.axis = r.require("axis").direction();
      desc.pivot = r.require("pivot").vec3();
      desc.degrees = r.require("degrees").number();
      r.number("duration", desc.duration, kNonNegative);
      b.driven.push_back(desc);
    }
  }
  if (auto e = o.get("strain_limit")) {
    if (b.elements != "tet") e->fail("strain limits need tet elements (set \"elements\": \"tet\" or use 'tet_mesh')");
    b.strain_limit = parse_strain_limit(Object(*e, {"smin", "smax", "mode", "pair_cuts", "frame_deg", "frame_regions"}));
  }
  return b;
}

const KeyList kObstacleTypes = {"plane", "box", "sphere", "capsule", "mesh"};

// Keys allowed for an obstacle of `type`; the reference point is "point" for a plane and
// "center" for the others.
KeyList obstacle_keys(const std::string& type) {
  KeyList keys{"type", "friction", "motion"};
  if (type == "plane") keys.insert(keys.end(), {"point", "normal"});
  if (type == "box") keys.insert(keys.end(), {"center", "half_extents", "rotation_deg"});
  if (type == "sphere") keys.insert(keys.end(), {"center", "radius"});
  if (type == "capsule") keys.insert(keys.end(), {"center", "radius", "length", "rotation_deg"});
  if (type == "mesh") keys.insert(keys.end(), {"mesh", "center", "rotation_deg", "scale"});
  return keys;
}

ObstacleMotion parse_motion(const Object& o) {
  ObstacleMotion m;
  if (o.one_of("velocity", "keyframes")) {
    m.velocity = o.require("velocity").vec3();
    return m;
  }
  for (const Node& n : o.require("keyframes").elements(true)) {
    const Object k(n, {"t", "position"});
    const Node t = k.require("t");
    ObstacleKeyframe frame{t.number(), k.require("position").vec3()};
    if (!m.keyframes.empty() && !(frame.t > m.keyframes.back().t))
      t.expected("a time greater than the previous keyframe's (" + number_text(m.keyframes.back().t) + ")");
    m.keyframes.push_back(frame);
  }
  return m;
}

ObstacleDesc parse_obstacle(const Node& node) {
  const Object o(node);
  ObstacleDesc ob;
  ob.json_path = node.path();
  o.choice("type", ob.type, kObstacleTypes);
  o.check_keys(obstacle_keys(ob.type));
  const std::string origin_key = ob.type == "plane" ? "point" : "center";
  if (ob.type == "plane") {
    ob.kind = ObstacleDesc::Kind::Plane;
    if (auto n = o.get("normal")) ob.normal = n->direction();
  } else if (ob.type == "box") {
    ob.kind = ObstacleDesc::Kind::Box;
    ob.half_extents = o.require("half_extents").vec3(kPositive);
  } else if (ob.type == "sphere") {
    ob.kind = ObstacleDesc::Kind::Sphere;
    ob.radius = o.require("radius").number(kPositive);
  } else if (ob.type == "capsule") {
    ob.kind = ObstacleDesc::Kind::Capsule;
    ob.radius = o.require("radius").number(kPositive);
    ob.half_length = 0.5 * o.require("length").number(kNonNegative);
  } else {
    ob.kind = ObstacleDesc::Kind::Mesh;
    ob.mesh_path = resolve_mesh(o.require("mesh"));
    o.number("scale", ob.scale, kPositive);
  }
  if (auto r = o.get("rotation_deg")) ob.rotation = rotation_from_euler_deg(r->vec3());
  o.vec3(origin_key, ob.point);
  o.number("friction", ob.friction, kNonNegative);
  if (auto m = o.get("motion")) {
    ob.motion = parse_motion(Object(*m, {"velocity", "keyframes"}));
    // Keyframes place the obstacle at every time: a second, static position would be ignored.
    if (!ob.motion.keyframes.empty() && o.has(origin_key))
      o.require(origin_key).fail("not allowed with 'motion.keyframes' (the keyframes give the " +
                                 origin_key + " at every time)");
    if (!ob.motion.keyframes.empty()) ob.point = ob.motion.keyframes.front().position;
  }
  return ob;
}

SolverDesc parse_solver(const Object& o) {
  SolverDesc s;
  o.choice("linear", s.linear, {"cholmod", "pcg"});
  o.number("pcg_tolerance", s.pcg_tolerance, kPositive);
  o.integer("pcg_max_iterations", s.pcg_max_iterations, kPositive);
  o.integer("pgs_max_iterations", s.pgs_max_iterations, kPositive);
  o.number("pgs_tolerance", s.pgs_tolerance, kPositive);
  o.integer("pgs_subspace_interval", s.pgs_subspace_interval, kNonNegative);
  o.choice("pgs_sweeps", s.pgs_sweeps, {"active_set", "all_rows"});
  o.integer("sqp_max_iterations", s.sqp_max_iterations, kPositive);
  o.number("sqp_tolerance", s.sqp_tolerance, kPositive);
  o.number("sqp_position_tolerance", s.sqp_position_tolerance, kPositive);
  o.number("sqp_stall_tolerance", s.sqp_stall_tolerance, kNonNegative);
  o.choice("sqp_cap_extension", s.sqp_cap_extension, {"once", "none"});
  o.choice("sqp_restoration", s.sqp_restoration, {"accept", "none"});
  o.choice("sqp_kkt_stop", s.sqp_kkt_stop, {"on", "off"});
  o.choice("sqp_acceleration", s.sqp_acceleration, {"conjugate", "none"});
  o.choice("sqp_solves", s.sqp_solves, {"shared", "separate"});
  o.choice("newton_predictor", s.newton_predictor, {"impulse", "none"});
  o.integer("refactor_interval", s.refactor_interval, kPositive);
  o.integer("curved_refactor_interval", s.curved_refactor_interval, kPositive);
  o.choice("stale_factor_precision", s.stale_factor_precision, {"single", "double"});
  o.number("hessian_reuse_tolerance", s.hessian_reuse_tolerance, kNonNegative);
  o.integer("delassus_reuse", s.delassus_reuse, kPositive);
  o.number("activation_margin", s.activation_margin, kFraction);
  o.number("contact_tolerance", s.contact_tolerance, kPositive);
  o.number("contact_margin", s.contact_margin, kNonNegative);
  o.number("body_friction", s.body_friction, kNonNegative);
  o.number("strain_tolerance", s.strain_tolerance, kPositive);
  o.number("max_speed", s.max_speed, kPositive);
  o.number("budget_violation_limit", s.budget_violation_limit, kPositive);
  o.number("divergence_violation_limit", s.divergence_violation_limit, kPositive);
  o.number("strain_activation_margin", s.strain_activation_margin, kNonNegative);
  o.integer("newton_max_iterations", s.newton_max_iterations, kPositive);
  o.number("newton_tolerance", s.newton_tolerance, kPositive);
  o.number("sleep_speed", s.sleep_speed, kNonNegative);
  o.number("sleep_acceleration", s.sleep_acceleration, kNonNegative);
  o.integer("sleep_steps", s.sleep_steps, kNonNegative);
  return s;
}

const KeyList kSolverKeys = {"linear",        "pcg_tolerance",      "pcg_max_iterations",
                             "pgs_max_iterations", "pgs_tolerance", "pgs_subspace_interval", "pgs_sweeps", "sqp_max_iterations",
                             "sqp_tolerance", "activation_margin", "contact_tolerance",
                             "contact_margin", "body_friction", "sqp_position_tolerance", "sqp_stall_tolerance", "sqp_cap_extension", "sqp_restoration", "sqp_kkt_stop", "sqp_acceleration", "sqp_solves", "newton_predictor",
                             "refactor_interval", "curved_refactor_interval", "stale_factor_precision", "hessian_reuse_tolerance", "delassus_reuse", "max_speed", "budget_violation_limit", "divergence_violation_limit", "strain_tolerance", "strain_activation_margin", "newton_max_iterations",
                             "newton_tolerance", "sleep_speed", "sleep_acceleration", "sleep_steps"};
const KeyList kSceneKeys = {"name",   "gravity", "h",      "fps",
                            "frames", "solver",  "bodies", "obstacles"};

SceneDesc parse_scene(const Node& root) {
  const Object o(root, kSceneKeys);
  SceneDesc s;
  s.name = fs::path(root.source().name).stem().string();
  o.string("name", s.name);
  o.vec3("gravity", s.gravity);
  o.number("h", s.h, kPositive);
  o.number("fps", s.fps, kPositive);
  o.integer("frames", s.frames, kPositive);
  if (auto n = o.get("solver")) s.solver = parse_solver(Object(*n, kSolverKeys));

  for (const Node& n : o.require("bodies").elements(true)) {
    const BodyDesc body = parse_body(n, s.bodies.size());
    for (const BodyDesc& other : s.bodies) {
      if (other.name == body.name)
        n.fail("duplicate body name '" + body.name + "' (also used by " + other.json_path + ")");
    }
    s.bodies.push_back(body);
  }
  if (auto obstacles = o.get("obstacles")) {
    for (const Node& n : obstacles->elements(false)) s.obstacles.push_back(parse_obstacle(n));
  }
  return s;
}

// ---- JSON text ----------------------------------------------------------------------

// nlohmann keeps the last of repeated object keys silently; this records the first repeat
// (with its path) so it can be reported. Fed by the parser callback.
class DuplicateKeyFinder {
 public:
  std::optional<std::pair<std::string, std::string>> found;  // {object path, repeated key}

  void on_event(json::parse_event_t event, const json& parsed) {
    using E = json::parse_event_t;
    switch (event) {
      case E::object_start:
      case E::array_start:
        stack_.push_back({child_path(), event == E::array_start, 0, "", {}});
        break;
      case E::object_end:
      case E::array_end: stack_.pop_back(); [[fallthrough]];
      case E::value:
        if (!stack_.empty() && stack_.back().is_array) ++stack_.back().index;
        break;
      case E::key: {
        Frame& top = stack_.back();
        top.key = parsed.get<std::string>();
        if (!top.keys.insert(top.key).second && !found) found = {top.path, top.key};
        break;
      }
    }
  }

 private:
  struct Frame {
    std::string path;
    bool is_array = false;
    std::size_t index = 0;  // next element (arrays)
    std::string key;        // current key (objects)
    std::set<std::string> keys;
  };
  std::vector<Frame> stack_;

  std::string child_path() const {
    if (stack_.empty()) return "";
    const Frame& top = stack_.back();
    return top.is_array ? index_path(top.path, top.index) : join(top.path, top.key);
  }
};

// ":LINE:COLUMN" (1-based, columns in UTF-8 characters) of byte `offset` in `text`.
std::string location(const std::string& text, std::size_t offset) {
  offset = std::min(offset, text.size());
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < offset; ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else if ((static_cast<unsigned char>(text[i]) & 0xC0) != 0x80) {
      ++column;
    }
  }
  return ":" + std::to_string(line) + ":" + std::to_string(column);
}

// nlohmann reports a number overflow without a position; locate the literal it quotes.
std::string overflow_location(const std::string& text, const std::string& message) {
  const std::size_t open = message.find('\''), close = message.rfind('\'');
  if (open == std::string::npos || close <= open) return "";
  const std::size_t at = text.find(message.substr(open + 1, close - open - 1));
  return at == std::string::npos ? "" : location(text, at);
}

// nlohmann's message without its "[json.exception...] parse error at ...: " prefix.
std::string strip_json_prefix(const std::string& what) {
  const std::size_t tag_end = what.find("] ");
  std::string s = tag_end == std::string::npos ? what : what.substr(tag_end + 2);
  if (s.rfind("parse error", 0) == 0) {
    const std::size_t colon = s.find(": ");
    if (colon != std::string::npos) s = s.substr(colon + 2);
  }
  return s;
}

// Scenes nest about 7 levels deep. The cap keeps a hostile file from costing memory
// quadratic in its depth (every open level holds its JSON path) and deep recursion in dump().
constexpr int kMaxJsonDepth = 64;

json parse_json(const std::string& text, const std::string& source_name) {
  DuplicateKeyFinder duplicates;
  json root;
  try {
    root = json::parse(text, [&](int depth, json::parse_event_t event, json& parsed) {
      if (depth > kMaxJsonDepth)
        throw InputError(source_name + ": invalid JSON: arrays and objects nested more than " +
                         std::to_string(kMaxJsonDepth) + " levels deep");
      duplicates.on_event(event, parsed);
      return true;
    });
  } catch (const json::parse_error& e) {
    // e.byte counts the characters read, the offending one included.
    throw InputError(source_name + location(text, e.byte == 0 ? 0 : e.byte - 1) +
                     ": invalid JSON: " + strip_json_prefix(e.what()));
  } catch (const json::exception& e) {  // e.g. a number too large for a double
    const std::string what = strip_json_prefix(e.what());
    throw InputError(source_name + overflow_location(text, what) + ": invalid JSON: " + what);
  }
  if (duplicates.found) {
    const auto& [path, key] = *duplicates.found;
    throw InputError(source_name + ": " + join(path, key) + ": duplicate key '" + key + "'");
  }
  return root;
}

}  // namespace

SceneDesc parse_scene_text(const std::string& text, const std::string& source_name,
                           const std::string& base_dir) {
  const json root = parse_json(text, source_name);
  const Source source{source_name, fs::path(base_dir)};
  return parse_scene(Node(root, "", source));
}

SceneDesc load_scene(const std::string& path) {
  std::error_code ec;
  std::ifstream in(path, std::ios::binary);
  if (!in || fs::is_directory(path, ec)) throw InputError(path + ": cannot open");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(path + ": cannot open");
  SceneDesc scene = parse_scene_text(text.str(), path, fs::path(path).parent_path().string());
  scene.path = path;
  return scene;
}

}  // namespace sinew
