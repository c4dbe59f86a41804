// Units as an open set: the registry's base units and conversions, values per unit parsed and
// converted at the edges, a unit a plug-in registers, and the simulation drawing per unit
// (px included) without assuming mm and rad.

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal {
namespace {

TEST(Units, BuiltInBaseUnitsAndTheirConversions) {
  EXPECT_TRUE(is_known_unit("mm"));
  EXPECT_TRUE(is_known_unit("rad"));
  EXPECT_TRUE(is_known_unit("px"));
  EXPECT_FALSE(is_known_unit("deg"));  // converted at the edges, never a quantity's unit
  EXPECT_FALSE(is_known_unit("m"));
  EXPECT_FALSE(is_known_unit("parsec"));
  Unit deg;
  ASSERT_TRUE(UnitRegistry::global().find("deg", &deg));
  EXPECT_EQ(deg.base, "rad");
  EXPECT_DOUBLE_EQ(deg.factor, kPi / 180);
  EXPECT_EQ(UnitRegistry::global().units_of("mm"), (std::vector<std::string>{"mm", "m"}));
}

TEST(Units, ValuesPerUnitAreConvertedToTheirBaseUnit) {
  const UnitValues v = UnitValues::parse("2e-5m,0.5deg,0.3px");
  EXPECT_DOUBLE_EQ(v.get("mm"), 0.02);
  EXPECT_DOUBLE_EQ(v.get("rad"), 0.5 * kPi / 180);
  EXPECT_DOUBLE_EQ(v.get("px"), 0.3);
  EXPECT_FALSE(v.has("m"));
  EXPECT_DOUBLE_EQ(UnitValues::parse("5").get("mm"), 5);  // a bare number is mm
  try {
    UnitValues::parse("5mm,0.001m");
    FAIL() << "two values in mm were accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("in mm twice"), std::string::npos) << e.what();
  }
  try {
    UnitValues::parse("3parsec");
    FAIL() << "an unknown unit was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("unknown unit 'parsec' (expected one of mm, m, rad"),
              std::string::npos)
        << e.what();
  }
}

TEST(Units, APlugInRegistersItsOwnUnitAndConversions) {
  UnitRegistry& units = UnitRegistry::global();
  if (!is_known_unit("N")) units.add_base("N", "a force");
  Unit kn;
  if (!units.find("kN", &kn)) units.add_alias("kN", "N", 1000);
  EXPECT_TRUE(is_known_unit("N"));
  EXPECT_DOUBLE_EQ(UnitValues::parse("0.002kN").get("N"), 2);
  EXPECT_THROW(units.add_base("N", "a force"), std::invalid_argument);       // known already
  EXPECT_THROW(units.add_alias("lbf", "lb", 4.448), std::invalid_argument);  // no such base
  EXPECT_THROW(units.add_alias("x", "N", -1), std::invalid_argument);
  EXPECT_THROW(units.add_base("N/m", "a stiffness"), std::invalid_argument);  // not a name
}

TEST(Units, TheScenarioDrawsPerUnitWithoutAssumingMmAndRad) {
  ScenarioOptions o;
  o.noise_half_width = UnitValues::parse("0.01mm,0.5px");
  EXPECT_DOUBLE_EQ(o.noise_for("px"), 0.5);
  EXPECT_DOUBLE_EQ(o.noise_for("rad"), 0);  // a unit not given: no noise
  EXPECT_DOUBLE_EQ(o.param_error_for("mm"), 5);
  EXPECT_DOUBLE_EQ(o.param_error_for("px"), 0);  // not the mm value
  EXPECT_TRUE(std::isnan(o.config_range_for("px")));
  EXPECT_DOUBLE_EQ(o.prior_std_for("px"), 0);
}

}  // namespace
}  // namespace kincal
