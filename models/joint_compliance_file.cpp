#include "kincal/models/joint_compliance_file.hpp"

#include <set>
#include <string>

#include "kincal/framework/base/message_excerpt.hpp"

namespace kincal {

using namespace json_field;

namespace {

PointMass read_point_mass(const Json& j, const JsonPath& at, std::set<std::string> more = {}) {
  object(j, at);
  more.insert({"mass_kg", "centre"});
  check_keys(j, at, more);
  PointMass m;
  m.mass = number_or(j, "mass_kg", 0.0, at);
  if (!(m.mass >= 0)) (at / "mass_kg").fail("expected a mass >= 0 kg");
  if (const Json* c = optional(j, "centre")) m.centre = vector3(*c, at / "centre");
  return m;
}

}  // namespace

ComplianceSpec read_compliance(const Json& j, const JsonPath& at, std::size_t joints) {
  object(j, at);
  check_keys(j, at, {"masses", "masses_source", "links", "gravity", "payload", "values"});
  ComplianceSpec c;
  c.enabled = true;
  const std::string masses = string(member(j, "masses", at), at / "masses");
  if (masses == "given")
    c.masses = GravityMasses::kGiven;
  else if (masses == "fitted")
    c.masses = GravityMasses::kFitted;
  else
    (at / "masses")
        .fail("expected \"given\" or \"fitted\", got \"" + message_excerpt(masses) + "\"");
  if (const Json* s = optional(j, "masses_source"))
    c.masses_source = string(*s, at / "masses_source");
  if (const Json* links = optional(j, "links")) {
    if (c.masses == GravityMasses::kFitted)
      (at / "links").fail("fitted masses take no links (their moments are parameters)");
    if (!links->is_array() || links->size() != joints)
      (at / "links")
          .fail("expected an array of " + std::to_string(joints) +
                " link masses, one per moving joint");
    for (std::size_t i = 0; i < links->size(); ++i)
      c.links.push_back(read_point_mass((*links)[i], (at / "links")[i]));
  } else if (c.masses == GravityMasses::kGiven) {
    (at / "links").fail("\"given\" masses need \"links\": a mass per moving joint");
  }
  if (const Json* g = optional(j, "gravity")) {
    c.gravity = vector3(*g, at / "gravity");
    if (!(c.gravity.norm() > 1e-9)) (at / "gravity").fail("expected a non-zero direction");
  }
  if (const Json* p = optional(j, "payload")) {
    const JsonPath pa = at / "payload";
    c.payload = read_point_mass(*p, pa, {"column", "max_kg"});
    if (const Json* col = optional(*p, "column")) {
      if (!col->is_boolean()) (pa / "column").fail("expected true or false");
      c.payload_column = col->get<bool>();
    }
    if (const Json* m = optional(*p, "max_kg")) {
      c.payload_max = number(*m, pa / "max_kg");
      if (!(c.payload_max > 0)) (pa / "max_kg").fail("expected a mass > 0 kg");
    }
  }
  if (const Json* v = optional(j, "values")) {
    object(*v, at / "values");
    for (const auto& [key, value] : v->items())
      c.values.emplace_back(key, number(value, at / "values" / key));
  }
  return c;
}

Json compliance_json(const ComplianceSpec& c) {
  Json out;
  out["masses"] = to_string(c.masses);
  if (!c.masses_source.empty()) out["masses_source"] = c.masses_source;
  if (c.masses == GravityMasses::kGiven) {
    out["links"] = Json::array();
    for (const PointMass& m : c.links)
      out["links"].push_back({{"mass_kg", m.mass}, {"centre", array3(m.centre)}});
  }
  out["gravity"] = array3(c.gravity);
  Json payload = {{"mass_kg", c.payload.mass}, {"centre", array3(c.payload.centre)}};
  if (c.payload_column) {
    payload["column"] = true;
    payload["max_kg"] = c.payload_max;
  }
  out["payload"] = payload;
  Json values = Json::object();
  for (const auto& [name, value] : c.values) values[name] = value;
  out["values"] = values;
  return out;
}

}  // namespace kincal
