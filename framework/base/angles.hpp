#pragma once
// pi and the degree conversions, one definition for every layer. Files read and written in
// degrees convert with these products (json_field::radians_from_degrees,
// degrees_reading_back): a second spelling of the same constant is how two readers come to
// differ at the last bit.

namespace kincal {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kRadiansPerDegree = kPi / 180;
inline constexpr double kDegreesPerRadian = 180 / kPi;

}  // namespace kincal
