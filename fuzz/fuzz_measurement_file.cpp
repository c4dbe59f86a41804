// libFuzzer target: the measurement CSV reader (framework/calibration/measurement_file.hpp),
// and its reader of a text column (parse_csv_text_column).
// Any input must either be read or be refused with std::invalid_argument carrying one short
// line; what is read must be finite and must survive a write/read round trip bit for bit.
// Small limits, so that the line- and file-size paths are reached by short inputs.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "kincal/framework/calibration/measurement_file.hpp"

namespace {

const std::vector<std::string> kActuators = {"leg1", "leg2", "leg3"};
const std::vector<std::string> kReadings = {"gauge", "t"};

[[noreturn]] void fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz_measurement_file: %s: %s\n", what, detail.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  kincal::CsvLimits limits;
  limits.max_line_bytes = 256;
  limits.max_file_bytes = 4096;
  const std::string text(reinterpret_cast<const char*>(data), size);
  // The text column reader (the images of `kincal detect`'s rows): read or refused in one
  // line, and a data row's line at most once.
  try {
    std::istringstream column_in(text);
    const auto column = kincal::parse_csv_text_column(column_in, "F.csv", "image", limits);
    for (const auto& [line, value] : column)
      if (line < 2 || value.find('\n') != std::string::npos) fail("text column", value);
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    if (what.rfind("F.csv", 0) != 0 || what.find('\n') != std::string::npos || what.size() > 400)
      fail("text column message", what);
  }
  std::istringstream in(text);
  kincal::MeasurementTable table;
  try {
    table = kincal::parse_measurements(in, "F.csv", kActuators, kReadings, limits);
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    if (what.rfind("F.csv", 0) != 0) fail("message does not name the file", what);
    if (what.find('\n') != std::string::npos || what.find('\0') != std::string::npos)
      fail("message is not one line", what);
    if (what.size() > 400) fail("message too long", what);
    return 0;
  }
  const kincal::Measurements& m = table.data;
  if (m.size() < 1) fail("no rows but no error", "");
  if (static_cast<int>(table.line_numbers.size()) != m.size()) fail("line numbers", "");
  for (std::size_t i = 1; i < table.line_numbers.size(); ++i)
    if (table.line_numbers[i] <= table.line_numbers[i - 1]) fail("line numbers not increasing", "");
  // An empty reading field is a reading not taken (NaN); nothing else may be non-finite.
  if (!m.actuators.allFinite()) fail("non-finite actuator value read", "");
  if ((m.readings.array().isInf()).any()) fail("infinite reading read", "");
  // What was read writes and reads back bit for bit (with the default limits: a written row
  // of 17-digit numbers may be longer than the small ones above).
  const std::string csv = kincal::measurements_to_csv(m, kActuators, kReadings, "round trip");
  std::istringstream again(csv);
  const kincal::MeasurementTable back =
      kincal::parse_measurements(again, "round-trip.csv", kActuators, kReadings);
  const bool same_readings = (back.data.readings.array() == m.readings.array() ||
                              (back.data.readings.array().isNaN() && m.readings.array().isNaN()))
                                 .all();
  if (back.data.actuators != m.actuators || !same_readings)
    fail("round trip changed the values", csv);
  return 0;
}
