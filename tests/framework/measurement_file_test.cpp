// Measurement CSV: columns by name, comments, notices, and every malformed-input error.

#include "kincal/framework/calibration/measurement_file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

const std::vector<std::string> kActuators = {"leg1", "leg2", "leg3", "leg4", "leg5", "leg6"};
const std::vector<std::string> kReadings = {"gauge"};

MeasurementTable parse(const std::string& text) {
  std::istringstream in(text);
  return parse_measurements(in, "D.csv", kActuators, kReadings);
}

// The message of the std::invalid_argument thrown by parse(text).
std::string error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(MeasurementFile, ReadsColumnsByNameSkippingCommentsAndIgnoringExtras) {
  const auto t = parse(
      "# recorded 2024-05-01\n"
      "\n"
      "gauge, temperature, leg6,leg5,leg4,leg3,leg2,leg1\r\n"
      "300.5, 21.0, 6,5,4,3,2,1\n"
      "# a comment between rows\n"
      "301.5, 21.5, 16,15,14,13,12,11\n");
  ASSERT_EQ(t.data.size(), 2);
  EXPECT_EQ(t.data.actuators(0, 0), 1);
  EXPECT_EQ(t.data.actuators(1, 5), 16);
  EXPECT_EQ(t.data.readings(1, 0), 301.5);
  EXPECT_EQ(t.line_numbers, (std::vector<int>{4, 6}));
  ASSERT_EQ(t.notices.size(), 1u);
  EXPECT_NE(t.notices[0].find("D.csv:3: ignoring column 'temperature'"), std::string::npos);
}

TEST(MeasurementFile, WrittenCsvReadsBackBitForBit) {
  Measurements m;
  m.actuators = MatrixXd::Random(5, 6) * 400;
  m.readings = MatrixXd::Random(5, 1) * 300;
  const std::string csv = measurements_to_csv(m, kActuators, kReadings, "two\nlines");
  EXPECT_EQ(csv.rfind("# two\n# lines\nleg1,leg2,leg3,leg4,leg5,leg6,gauge\n", 0), 0u);
  const auto t = parse(csv);
  EXPECT_EQ(t.data.actuators, m.actuators);
  EXPECT_EQ(t.data.readings, m.readings);
}

TEST(MeasurementFile, EveryMalformedInputNamesFileLineAndExpectation) {
  const std::string header = "leg1,leg2,leg3,leg4,leg5,leg6,gauge\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"", "D.csv: no header row (expected columns leg1,leg2,leg3,leg4,leg5,leg6,gauge)"},
      {"# only a comment\n", "D.csv: no header row"},
      {header, "D.csv: no measurement rows"},
      {"leg1,leg2,leg3,leg4,leg5,gauge\n1,2,3,4,5,6\n", "D.csv:1: header has no column 'leg6'"},
      {"leg1,leg2,leg3,leg4,leg5,leg6,leg2,gauge\n",
       "D.csv:1: column 'leg2' appears twice (fields 2 and 7)"},
      {header + "1,2,3,4,5,6,7\n1,2,3,4,5,6\n", "D.csv:3: 6 fields, expected 7 as in the header"},
      {header + "1,2,3,4,5,6,7,8\n", "D.csv:2: 8 fields, expected 7"},
      {header + "1,2,abc,4,5,6,7\n", "D.csv:2: field 'leg3': 'abc' is not a number"},
      {header + "1,2,3,4,5,6,12.5mm\n", "D.csv:2: field 'gauge': '12.5mm' is not a number"},
      {header + "1,2,3,4,5,nan,7\n", "D.csv:2: field 'leg6': 'nan' is not a finite number"},
      {header + "1,2,3,4,5,6,-inf\n", "D.csv:2: field 'gauge': '-inf' is not a finite number"},
      {header + "1,2,3,4,5,6,1e999\n",
       "D.csv:2: field 'gauge': '1e999' is beyond the range of a double (magnitude above 1.8e308)"},
      {header + "1,,3,4,5,6,7\n", "D.csv:2: field 'leg2' is empty, expected a number"},
  };
  for (const auto& [text, expected] : cases) {
    const std::string what = error_of(text);
    EXPECT_NE(what.find(expected), std::string::npos) << "got: " << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

// strtod stops at a NUL byte, so "336.81\0junk" used to read as 336.81.
TEST(MeasurementFile, ANulByteIsAnErrorNotTheEndOfTheValue) {
  const std::string header = "leg1,leg2,leg3,leg4,leg5,leg6,gauge\n";
  const std::string text =
      header + "1,2,3,4,5,6,7\n1,2,3,4,5,6," + std::string("336.81\0junk", 11) + "\n";
  EXPECT_EQ(error_of(text), "D.csv:3: NUL byte at column 19; expected a text file (CSV)");
  EXPECT_EQ(error_of(std::string("leg1\0", 5)),
            "D.csv:1: NUL byte at column 5; expected a text file (CSV)");
}

// Spreadsheets write "CSV UTF-8" with a byte order mark; it read as part of the first name.
TEST(MeasurementFile, AByteOrderMarkIsSkipped) {
  const auto t = parse("\xEF\xBB\xBFleg1,leg2,leg3,leg4,leg5,leg6,gauge\n1,2,3,4,5,6,7\n");
  ASSERT_EQ(t.data.size(), 1);
  EXPECT_EQ(t.data.actuators(0, 0), 1);
  EXPECT_TRUE(t.notices.empty());
}

// 1e-400 is a number; it rounds to zero as 0.1 rounds to the nearest double. It used to be
// called "not a finite number".
TEST(MeasurementFile, UnderflowRoundsToZero) {
  const auto t = parse("leg1,leg2,leg3,leg4,leg5,leg6,gauge\n1e-400,2,3,4,5,6,-1e-320\n");
  EXPECT_EQ(t.data.actuators(0, 0), 0.0);
  EXPECT_LT(t.data.readings(0, 0), 0.0);  // a subnormal number, sign kept
  EXPECT_GT(t.data.readings(0, 0), -1e-319);
}

// A file without line breaks (/dev/zero, a binary, a huge log) used to be read whole into one
// line before anything was said.
TEST(MeasurementFile, LinesAndFilesHaveSizeLimits) {
  const std::string header = "leg1,leg2,leg3,leg4,leg5,leg6,gauge\n";
  const std::string long_line = header + std::string(100'000, '1') + "\n";
  EXPECT_EQ(
      error_of(long_line),
      "D.csv:2: line longer than the limit of 65536 bytes; expected a measurement file (CSV)");
  // Exactly at the limit is fine (the value is then read and judged as a number).
  CsvLimits limits;
  limits.max_line_bytes = 13;
  limits.max_file_bytes = 60;
  auto parse_limited = [&](const std::string& text) {
    std::istringstream in(text);
    return parse_measurements(in, "D.csv", {"a", "b"}, {"g"}, limits);
  };
  EXPECT_EQ(parse_limited("a,b,g\n1.0000001,2,3\n").data.size(), 1);
  EXPECT_THROW(parse_limited("a,b,g\n1.00000001,2,3\n"), std::invalid_argument);
  try {
    parse_limited(
        "a,b,g\n1,2,3\n1,2,3\n1,2,3\n1,2,3\n1,2,3\n1,2,3\n1,2,3\n1,2,3\n1,2,3\n1,2,3\n");  // 66
                                                                                           // bytes
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "D.csv: larger than the limit of 0 MiB (60 bytes) for a measurement file");
  }
  // Memory for the rows read (the command line sets it from the machine): the row that would
  // not fit is named. Rows of 3 values take table_bytes_per_row(3) = 112 bytes.
  CsvLimits memory;
  memory.max_table_bytes = 3 * table_bytes_per_row(3);
  std::istringstream three("a,b,g\n1,2,3\n1,2,3\n1,2,3\n");
  EXPECT_EQ(parse_measurements(three, "D.csv", {"a", "b"}, {"g"}, memory).data.size(), 3);
  std::istringstream four("a,b,g\n1,2,3\n1,2,3\n1,2,3\n1,2,3\n");
  try {
    parse_measurements(four, "D.csv", {"a", "b"}, {"g"}, memory);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "D.csv:5: the rows read so far need more than the 0 MiB of memory allowed for "
                 "them; expected a smaller file");
  }
  // The default file limit covers what kincal writes (simulate --poses 1000000 is 132 MB)
  // and an hour of a tracker logging at 1 kHz.
  EXPECT_GE(CsvLimits{}.max_file_bytes, std::size_t{1} << 30);
  // /dev/zero: stops at once, on the first NUL byte.
  try {
    read_measurements("/dev/zero", kActuators, kReadings);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "/dev/zero:1: NUL byte at column 1; expected a text file (CSV)");
  }
}

TEST(MeasurementFile, MessagesQuoteAtMostAShortExcerpt) {
  const std::string header = "leg1,leg2,leg3,leg4,leg5,leg6,gauge\n";
  const std::string what = error_of(header + "1,2,3,4,5,6," + std::string(60'000, 'x') + "\n");
  EXPECT_LT(what.size(), 200u) << what;
  EXPECT_NE(what.find("D.csv:2: field 'gauge': 'xxxx"), std::string::npos) << what;
  EXPECT_NE(what.find("...' is not a number"), std::string::npos) << what;
}

TEST(MeasurementFile, MissingFileIsAnError) {
  try {
    read_measurements("/nonexistent/D.csv", kActuators, kReadings);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/D.csv: cannot open"), std::string::npos);
  }
}

// An ifstream opens a directory and reads nothing: that must not read as "no header row".
TEST(MeasurementFile, DirectoryIsNamedAsSuch) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("kincal-measurement-dir-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::string what = "(no error)";
  try {
    read_measurements(dir.string(), kActuators, kReadings);
  } catch (const std::invalid_argument& e) {
    what = e.what();
  }
  std::filesystem::remove(dir);
  EXPECT_EQ(what, dir.string() + ": is a directory, expected a measurement file (CSV)");
}

TEST(MeasurementFile, FindsUnreachableRowsAndDropsThem) {
  const auto model = make_cube_hexapod();
  const VectorXd p = model->parameters().nominal_values();
  const auto t = parse(
      "leg1,leg2,leg3,leg4,leg5,leg6,gauge\n"
      "354,354,354,354,354,382,300\n"
      "-354,354,354,354,354,382,300\n"
      "354,354,354,354,354,382,300\n"
      "3540,10,10,354,354,382,300\n");
  const auto bad = find_unreachable_rows(*model, p, t.data);
  ASSERT_EQ(bad.size(), 2u);
  EXPECT_EQ(bad[0].row, 1);
  EXPECT_NE(bad[0].reason.find("actuator values are invalid"), std::string::npos);
  EXPECT_EQ(bad[1].row, 3);
  const Measurements kept = drop_rows(t.data, {1, 3});
  ASSERT_EQ(kept.size(), 2);
  EXPECT_TRUE(find_unreachable_rows(*model, p, kept).empty());
}

}  // namespace
}  // namespace kincal

namespace kincal {
namespace {

// Issue 14: semicolon- and tab-separated files are read as their comma-separated twin when
// the header says so unambiguously; a decimal comma is refused, never misread.
TEST(MeasurementFileSeparators, SemicolonAndTabFilesReadAsTheCommaFile) {
  const std::string comma = "leg1,leg2,leg3,leg4,leg5,leg6,gauge\n1.5,2,3,4,5,6,300.25\n";
  const auto expected = parse(comma);
  for (const char separator : {';', '\t'}) {
    std::string text = comma;
    for (char& c : text)
      if (c == ',') c = separator;
    const auto t = parse(text);
    EXPECT_EQ(t.data.actuators, expected.data.actuators);
    EXPECT_EQ(t.data.readings, expected.data.readings);
    ASSERT_FALSE(t.notices.empty());
    EXPECT_NE(t.notices[0].find("D.csv:1: fields separated by"), std::string::npos) << t.notices[0];
  }
  EXPECT_TRUE(parse(comma).notices.empty());
}

TEST(MeasurementFileSeparators, DecimalCommaAndMixedSeparatorsAreOneLineErrors) {
  EXPECT_NE(error_of("leg1;leg2;leg3;leg4;leg5;leg6;gauge\n1,5;2;3;4;5;6;300\n")
                .find("D.csv:2: field 'leg1': '1,5' has a decimal comma"),
            std::string::npos);
  EXPECT_NE(error_of("leg1\tleg2\tleg3\tleg4\tleg5\tleg6\tgauge\n1\t2\t3\t4\t5\t6\t300,5\n")
                .find("field 'gauge': '300,5' has a decimal comma (fields are separated by tabs)"),
            std::string::npos);
  EXPECT_NE(
      error_of("leg1;leg2;leg3;leg4;leg5;leg6,gauge\n").find("the header holds commas and ';'"),
      std::string::npos);
  EXPECT_NE(error_of("leg1;leg2\tleg3;leg4;leg5;leg6;gauge\n").find("both ';' and tabs"),
            std::string::npos);
}

}  // namespace
}  // namespace kincal

namespace kincal {
namespace {

TEST(MeasurementFileTextColumn, GivesEachDataRowsFieldByLineOrNothingWithoutTheColumn) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("kincal-text-column-" + std::to_string(::getpid()) + ".csv");
  {
    std::ofstream out(path);
    out << "\xEF\xBB\xBFimage,leg1\n# a comment\nimages/a.png,1\n\n b.png ,2\n3\n";
  }
  const auto column = read_csv_text_column(path.string(), "image");
  EXPECT_EQ(column, (std::map<int, std::string>{{3, "images/a.png"}, {5, "b.png"}, {6, "3"}}));
  EXPECT_TRUE(read_csv_text_column(path.string(), "label").empty());
  std::filesystem::remove(path);
  EXPECT_THROW(read_csv_text_column(path.string(), "image"), std::invalid_argument);
}

}  // namespace
}  // namespace kincal
