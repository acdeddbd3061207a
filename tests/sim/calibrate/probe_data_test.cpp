// The probe CSV (sim/calibrate/probe_data.h): what probe_csv writes is read back exactly; the
// layout may vary (column order, extra columns, CRLF, blank lines, spaces) without changing what is
// read; every kind of bad file is refused with a CalibrationError naming the problem and where it
// is; and damaged text is either read or refused, never anything else.
#include "sim/calibrate/probe_data.h"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <random>
#include <string>
#include <typeinfo>
#include <vector>

namespace incise::sim::calibrate {
namespace {

// Whether message contains part. (GoogleTest only: the suites do not link gmock's HasSubstr.)
::testing::AssertionResult mentions(const std::string& message, const std::string& part) {
  if (message.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << message << "' does not mention '" << part << "'";
}

// The message of the CalibrationError that parsing text throws; a failure when it parses or throws
// anything else.
std::string refusal(std::string_view text) {
  try {
    parse_probe_csv(text);
  } catch (const CalibrationError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "threw " << typeid(e).name() << " (" << e.what() << "), not CalibrationError";
    return {};
  }
  ADD_FAILURE() << "read, but should have been refused:\n" << text;
  return {};
}

::testing::AssertionResult bit_equal(Real a, Real b) {
  if (std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b)) {
    return ::testing::AssertionSuccess();
  }
  char text[80];
  std::snprintf(text, sizeof text, "%.17g and %.17g differ", a, b);
  return ::testing::AssertionFailure() << text;
}

std::string join(const std::vector<std::string>& lines, const std::string& end = "\n") {
  std::string text;
  for (const std::string& line : lines)
    text += line + end;
  return text;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  for (std::size_t comma; (comma = line.find(',', start)) != std::string::npos; start = comma + 1)
    fields.push_back(line.substr(start, comma - start));
  fields.push_back(line.substr(start));
  return fields;
}

// A good file: two contacts pressed straight down (-z), 1 ms between samples, at rest (no force)
// at the first sample. Line n of the file is kGood[n - 1].
const std::vector<std::string> kGood = {
    "time_s,contact,x,y,z,dir_x,dir_y,dir_z,force_n",
    "0,0,0.01,0.02,0.05,0,0,-1,0",  // line 2
    "0.001,0,0.01,0.02,0.0499,0,0,-1,0.25",
    "0.002,0,0.01,0.02,0.0498,0,0,-1,0.5",
    "0.003,0,0.01,0.02,0.0497,0,0,-1,0.75",  // line 5
    "0.004,0,0.01,0.02,0.0496,0,0,-1,1",
    "0.005,0,0.01,0.02,0.0495,0,0,-1,1.25",
    "0.5,3,-0.02,0.01,0.05,0,0,-1,0",  // line 8
    "0.501,3,-0.02,0.01,0.0498,0,0,-1,0.4",
    "0.502,3,-0.02,0.01,0.0496,0,0,-1,0.8",
    "0.503,3,-0.02,0.01,0.0494,0,0,-1,1.2",
    "0.504,3,-0.02,0.01,0.0492,0,0,-1,1.6",
    "0.505,3,-0.02,0.01,0.049,0,0,-1,2",  // line 13
};

// Two contacts, ids 0 and 3, six samples 1 ms apart each: the probe presses along a slanted unit
// direction, deeper and harder at each sample; the values need all 17 digits, or an exponent.
ProbeData two_contacts() {
  const std::array<int, 2> ids = {0, 3};
  const std::array<Vec3, 2> directions = {Vec3(0.48, 0.6, -0.64), Vec3(-0.28, 0.96, 0)};
  const std::array<Vec3, 2> touch = {Vec3(1.0 / 3, -0.0305, 3.2e-7), Vec3(-0.0021, 0.0333, 0.05)};
  ProbeData data;
  data.step = 0.001;
  for (std::size_t c = 0; c < 2; ++c) {
    ProbeContact contact;
    contact.id = ids[c];
    for (int k = 0; k < 6; ++k) {
      ProbeSample s;
      s.time = 0.25 * static_cast<Real>(c) + 0.001 * k;
      s.direction = directions[c];
      s.position = touch[c] + (0.00037 * k + 1e-9 * k * k) * directions[c];
      s.force = 0.173 * k + 1.7e-6 * k * k;
      contact.samples.push_back(s);
    }
    data.contacts.push_back(contact);
  }
  return data;
}

// Same contacts, samples and step, value for value (bit for bit); directions to a few ulps, as
// reading normalises them.
void expect_same(const ProbeData& read, const ProbeData& expected) {
  EXPECT_TRUE(bit_equal(read.step, expected.step)) << "step";
  ASSERT_EQ(read.contacts.size(), expected.contacts.size());
  for (std::size_t c = 0; c < read.contacts.size(); ++c) {
    const ProbeContact& a = read.contacts[c];
    const ProbeContact& b = expected.contacts[c];
    EXPECT_EQ(a.id, b.id);
    ASSERT_EQ(a.samples.size(), b.samples.size()) << "contact " << b.id;
    for (std::size_t k = 0; k < a.samples.size(); ++k) {
      SCOPED_TRACE("contact " + std::to_string(b.id) + ", sample " + std::to_string(k));
      EXPECT_TRUE(bit_equal(a.samples[k].time, b.samples[k].time));
      for (int i = 0; i < 3; ++i)
        EXPECT_TRUE(bit_equal(a.samples[k].position[i], b.samples[k].position[i])) << "x" << i;
      EXPECT_TRUE(bit_equal(a.samples[k].force, b.samples[k].force));
      EXPECT_LT((a.samples[k].direction - b.samples[k].direction).norm(), 1e-15);
    }
  }
}

TEST(ProbeCsv, IsReadBackExactly) {
  const ProbeData data = two_contacts();
  const ProbeData read = parse_probe_csv(probe_csv(data));
  expect_same(read, data);
  for (const ProbeContact& contact : read.contacts)
    for (const ProbeSample& s : contact.samples)
      EXPECT_NEAR(s.direction.norm(), 1, 1e-15);
}

TEST(ParseProbeCsv, ColumnsMayComeInAnyOrderAndOtherColumnsAreIgnored) {
  // kGood's columns shuffled, with a text column first and a number column in the middle.
  const std::array<std::size_t, 9> order = {8, 5, 0, 7, 2, 1, 6, 4, 3};
  std::vector<std::string> lines;
  for (std::size_t n = 0; n < kGood.size(); ++n) {
    const std::vector<std::string> fields = split(kGood[n]);
    std::string line = n == 0 ? "note" : "pressed by hand";
    for (std::size_t i = 0; i < order.size(); ++i) {
      line += "," + fields[order[i]];
      if (i == 3) line += n == 0 ? ",temperature_c" : ",21.5";
    }
    lines.push_back(line);
  }
  expect_same(parse_probe_csv(join(lines)), parse_probe_csv(join(kGood)));
}

TEST(ParseProbeCsv, ContactsMayInterleaveAndComeInAnyOrder) {
  // Contact 3's rows first, then alternating: each contact's samples are still in time order.
  std::vector<std::string> lines = {kGood[0]};
  for (std::size_t k = 0; k < 6; ++k) {
    lines.push_back(kGood[7 + k]);
    lines.push_back(kGood[1 + k]);
  }
  const ProbeData read = parse_probe_csv(join(lines));
  ASSERT_EQ(read.contacts.size(), 2u);
  EXPECT_EQ(read.contacts[0].id, 0);
  EXPECT_EQ(read.contacts[1].id, 3);
  expect_same(read, parse_probe_csv(join(kGood)));
}

TEST(ParseProbeCsv, AcceptsCrlfBlankLinesAndSpacesAroundFields) {
  const ProbeData expected = parse_probe_csv(join(kGood));
  std::vector<std::string> lines;
  for (const std::string& line : kGood) {
    std::string spaced = " ";
    for (const char c : line)
      spaced += c == ',' ? std::string(" ,\t") : std::string(1, c);
    lines.push_back(spaced + " \t");
    lines.push_back(lines.size() % 3 == 0 ? "  " : "");  // blank, or only spaces
  }
  SCOPED_TRACE(join(lines, "\r\n"));
  expect_same(parse_probe_csv(join(lines, "\r\n")), expected);
  expect_same(parse_probe_csv("\r\n\n" + join(kGood, "\r\n") + "\r\n\r\n"), expected);
  // No line end after the last row.
  std::string unterminated = join(kGood, "\r\n");
  unterminated.resize(unterminated.size() - 2);
  expect_same(parse_probe_csv(unterminated), expected);
}

TEST(ParseProbeCsv, NormalisesTheDirection) {
  const auto direction_read = [](const std::string& dir_xyz) {
    std::vector<std::string> lines = kGood;
    for (std::size_t n = 1; n < lines.size(); ++n) {
      std::vector<std::string> fields = split(lines[n]);
      const std::vector<std::string> xyz = split(dir_xyz);
      lines[n] = fields[0] + "," + fields[1] + "," + fields[2] + "," + fields[3] + "," + fields[4] +
                 "," + xyz[0] + "," + xyz[1] + "," + xyz[2] + "," + fields[8];
    }
    const ProbeData data = parse_probe_csv(join(lines));
    for (const ProbeContact& contact : data.contacts)
      for (const ProbeSample& s : contact.samples)
        EXPECT_EQ(s.direction, data.contacts[0].samples[0].direction) << dir_xyz;
    return data.contacts[0].samples[0].direction;
  };
  EXPECT_EQ(direction_read("0,0,-2"), Vec3(0, 0, -1));
  EXPECT_EQ(direction_read("0,0.25,0"), Vec3(0, 1, 0));
  EXPECT_LT((direction_read("3,0,4") - Vec3(0.6, 0, 0.8)).norm(), 1e-15);
  EXPECT_LT((direction_read("1e-3,2e-3,-2e-3") - Vec3(1, 2, -2) / 3).norm(), 1e-15);
  EXPECT_LT((direction_read("-7, 1e2 ,0.5") - Vec3(-7, 100, 0.5).normalized()).norm(), 1e-15);
}

// A direction whose components are finite but huge (1e200), or tiny, has a norm that overflows
// or underflows: it is scaled first, and read as the unit direction it points along.
TEST(ParseProbeCsv, AHugeDirectionIsNotReadAsZero) {
  std::vector<std::string> lines = kGood;
  for (std::size_t n = 1; n < lines.size(); ++n) {
    const std::size_t at = lines[n].find(",0,0,-1,");
    ASSERT_NE(at, std::string::npos);
    lines[n].replace(at, 8, ",0,0,-1e200,");
  }
  const ProbeData data = parse_probe_csv(join(lines));
  EXPECT_EQ(data.contacts[0].samples[0].direction, Vec3(0, 0, -1));
}

// Spreadsheets save UTF-8 with a byte-order mark: it is not part of the first column's name.
TEST(ParseProbeCsv, ReadsAFileThatStartsWithAByteOrderMark) {
  const ProbeData plain = parse_probe_csv(join(kGood));
  const ProbeData marked = parse_probe_csv("\xEF\xBB\xBF" + join(kGood));
  ASSERT_EQ(marked.contacts.size(), plain.contacts.size());
  EXPECT_EQ(marked.contacts[1].samples[1].position, plain.contacts[1].samples[1].position);
}

TEST(ParseProbeCsv, RefusesTwoSigns) {
  std::vector<std::string> lines = kGood;
  lines[3] = "0.002,0,0.01,0.02,0.0498,0,0,-1,+-0.5";  // line 4
  EXPECT_TRUE(mentions(refusal(join(lines)), "line 4: force_n '+-0.5' is not a number"));
}

TEST(ParseProbeCsv, RefusesAMissingColumn) {
  const std::string rows = join({kGood.begin() + 1, kGood.end()});
  const std::string one = refusal("time_s,contact,x,y,z,dir_x,dir_y,dir_z\n" + rows);
  EXPECT_TRUE(mentions(one, "line 1: "));
  EXPECT_TRUE(mentions(one, "missing column force_n "));
  const std::string two = refusal("force_n,time_s,contact,y,dir_y,dir_z,x\n" + rows);
  EXPECT_TRUE(mentions(two, "line 1: "));
  EXPECT_TRUE(mentions(two, "missing columns z, dir_x "));
  // The header is the first line that is not blank; a misspelt name counts as missing.
  const std::string late = refusal("\n \r\ntime,contact,x,y,z,dir_x,dir_y,dir_z,force_n\n" + rows);
  EXPECT_TRUE(mentions(late, "line 3: "));
  EXPECT_TRUE(mentions(late, "missing column time_s "));
}

TEST(ParseProbeCsv, RefusesADuplicatedColumn) {
  const std::string rows = join({kGood.begin() + 1, kGood.end()});
  const std::string message = refusal("time_s,contact,x,y,z,dir_x,dir_y,dir_z,force_n,y\n" + rows);
  EXPECT_TRUE(mentions(message, "line 1: "));
  EXPECT_TRUE(mentions(message, "column y appears twice"));
}

TEST(ParseProbeCsv, RefusesAValueThatIsNotANumber) {
  for (const std::string bad : {"abc", "", "1.2.3", "0x10", "--1", "1 2", "5mm", "1e"}) {
    std::vector<std::string> lines = kGood;
    lines[3] = "0.002,0,0.01," + bad + ",0.0498,0,0,-1,0.5";
    SCOPED_TRACE("y = '" + bad + "'");
    EXPECT_TRUE(mentions(refusal(join(lines)), "line 4: y '" + bad + "' is not a number"));
  }
  std::vector<std::string> lines = kGood;
  lines[12] = "0.505,3,-0.02,0.01,0.049,0,0,-1,heavy";
  EXPECT_TRUE(mentions(refusal(join(lines)), "line 13: force_n 'heavy' is not a number"));
}

TEST(ParseProbeCsv, RefusesNanAndInfinity) {
  for (const std::string bad : {"nan", "NaN", "-nan", "inf", "-inf", "infinity", "1e400"}) {
    std::vector<std::string> lines = kGood;
    lines[5] = "0.004,0," + bad + ",0.02,0.0496,0,0,-1,1";
    const std::string message = refusal(join(lines));
    SCOPED_TRACE(bad);
    EXPECT_TRUE(mentions(message, "line 6: x '" + bad + "' is not a number"));
  }
  std::vector<std::string> lines = kGood;
  lines[2] = "inf,0,0.01,0.02,0.0499,0,0,-1,0.25";
  EXPECT_TRUE(mentions(refusal(join(lines)), "line 3: time_s 'inf' is not a number"));
}

TEST(ParseProbeCsv, RefusesAContactThatIsNotAWholeNumber) {
  for (const std::string bad : {"1.5", "0.000001", "-2.25"}) {
    std::vector<std::string> lines = kGood;
    lines[4] = "0.003," + bad + ",0.01,0.02,0.0497,0,0,-1,0.75";
    const std::string message = refusal(join(lines));
    SCOPED_TRACE(bad);
    EXPECT_TRUE(mentions(message, "line 5: contact '" + bad + "' is not a whole number"));
  }
}

TEST(ParseProbeCsv, RefusesAZeroDirection) {
  for (const std::string zero : {"0,0,0", "-0,0,0", "0, 0 ,0e5"}) {
    std::vector<std::string> lines = kGood;
    lines[9] = "0.502,3,-0.02,0.01,0.0496," + zero + ",0.8";
    SCOPED_TRACE(zero);
    EXPECT_TRUE(mentions(refusal(join(lines)), "line 10: the direction is zero"));
  }
}

TEST(ParseProbeCsv, RefusesANegativeForce) {
  std::vector<std::string> lines = kGood;
  lines[6] = "0.005,0,0.01,0.02,0.0495,0,0,-1,-0.5";
  const std::string message = refusal(join(lines));
  EXPECT_TRUE(mentions(message, "line 7: "));
  EXPECT_TRUE(mentions(message, "force_n -0.5 is negative"));
}

TEST(ParseProbeCsv, RefusesTooFewSamples) {
  // Contact 3 with 4 samples (lines 12 and 13 dropped): the message names the contact.
  const std::string message = refusal(join({kGood.begin(), kGood.end() - 2}));
  EXPECT_TRUE(mentions(message, "contact 3: 4 samples"));
  EXPECT_TRUE(mentions(message, "at least " + std::to_string(kMinSamplesPerContact)));
  EXPECT_TRUE(mentions(message, "at least 5"));
  // One sample.
  EXPECT_TRUE(mentions(refusal(join({kGood[0], kGood[1]})), "contact 0: 1 sample, at least 5"));
}

TEST(ParseProbeCsv, RefusesUnevenlySpacedSamples) {
  // Within a contact: contact 0's fourth sample half a step late.
  std::vector<std::string> lines = kGood;
  lines[4] = "0.0035,0,0.01,0.02,0.0497,0,0,-1,0.75";
  const std::string within = refusal(join(lines));
  EXPECT_TRUE(mentions(within, "contact 0: "));
  EXPECT_TRUE(mentions(within, "time_s 0.0035"));
  EXPECT_TRUE(mentions(within, "evenly spaced"));
  // Between contacts: contact 3 sampled every 2 ms, contact 0 every 1 ms.
  lines = kGood;
  for (std::size_t k = 0; k < 6; ++k)
    lines[7 + k].replace(0, lines[7 + k].find(','), std::to_string(0.5 + 0.002 * k));
  const std::string between = refusal(join(lines));
  EXPECT_TRUE(mentions(between, "contact 3: "));
  EXPECT_TRUE(mentions(between, "the data's step is 0.001 s"));
  EXPECT_TRUE(mentions(between, "evenly spaced"));
  // Within the tolerance (kStepTolerance of the step) is even.
  lines = kGood;
  lines[4] = "0.003001,0,0.01,0.02,0.0497,0,0,-1,0.75";
  EXPECT_NO_THROW(parse_probe_csv(join(lines)));
}

TEST(ParseProbeCsv, RefusesTimesThatDoNotIncrease) {
  std::vector<std::string> lines = kGood;
  lines[4] = "0.002,0,0.01,0.02,0.0497,0,0,-1,0.75";  // the same time as line 4
  const std::string same = refusal(join(lines));
  EXPECT_TRUE(mentions(same, "line 5: time_s 0.002 of contact 0 is not after 0.002"));
  lines = kGood;
  std::swap(lines[9], lines[10]);  // line 10 at 0.503 before line 11 at 0.502
  EXPECT_TRUE(mentions(refusal(join(lines)), "line 11: time_s 0.502 of contact 3 is not after"));
}

TEST(ParseProbeCsv, RefusesAContactWithNoForce) {
  std::vector<std::string> lines = kGood;
  for (std::size_t n = 7; n < lines.size(); ++n)
    lines[n] = lines[n].substr(0, lines[n].rfind(',')) + ",0";
  const std::string message = refusal(join(lines));
  EXPECT_TRUE(mentions(message, "contact 3: "));
  EXPECT_TRUE(mentions(message, "no contact"));
}

TEST(ParseProbeCsv, RefusesAnEmptyFile) {
  for (const std::string empty : {"", "\n", "\r\n\r\n", "  \t \n\n"}) {
    SCOPED_TRACE("'" + empty + "'");
    EXPECT_TRUE(mentions(refusal(empty), "the file is empty"));
  }
}

TEST(ParseProbeCsv, RefusesAHeaderWithNoRows) {
  EXPECT_TRUE(mentions(refusal(kGood[0]), "no samples after the header"));
  EXPECT_TRUE(mentions(refusal(kGood[0] + "\r\n\r\n \n"), "no samples after the header"));
}

TEST(ParseProbeCsv, RefusesARowWithTheWrongNumberOfFields) {
  std::vector<std::string> lines = kGood;
  lines[3] = "0.002,0,0.01,0.02,0.0498,0,0,-1";
  EXPECT_TRUE(mentions(refusal(join(lines)), "line 4: 8 values, the header has 9"));
  lines = kGood;
  lines[8] += ",7";
  EXPECT_TRUE(mentions(refusal(join(lines)), "line 9: 10 values, the header has 9"));
}

// What parse_probe_csv did with text: data that keeps the header's promises, or a CalibrationError
// with a one-line printable message; a failure for any other exception.
::testing::AssertionResult read_or_refused(std::string_view text) {
  try {
    const ProbeData data = parse_probe_csv(text);
    if (data.contacts.empty()) return ::testing::AssertionFailure() << "no contacts";
    if (!(data.step > 0) || !std::isfinite(data.step))
      return ::testing::AssertionFailure() << "step " << data.step;
    for (std::size_t c = 0; c < data.contacts.size(); ++c) {
      const ProbeContact& contact = data.contacts[c];
      if (c > 0 && contact.id <= data.contacts[c - 1].id)
        return ::testing::AssertionFailure() << "contacts out of order";
      if (static_cast<int>(contact.samples.size()) < kMinSamplesPerContact)
        return ::testing::AssertionFailure() << "contact " << contact.id << ": too few samples";
      bool pushed = false;
      for (std::size_t k = 0; k < contact.samples.size(); ++k) {
        const ProbeSample& s = contact.samples[k];
        if (!std::isfinite(s.time) || !s.position.allFinite() || !std::isfinite(s.force) ||
            s.force < 0 || std::abs(s.direction.norm() - 1) > 1e-12 ||
            (k > 0 && !(s.time > contact.samples[k - 1].time))) {
          return ::testing::AssertionFailure()
                 << "contact " << contact.id << ", sample " << k << " breaks the header's promises";
        }
        pushed = pushed || s.force > 0;
      }
      if (!pushed) return ::testing::AssertionFailure() << "contact " << contact.id << ": no force";
    }
    return ::testing::AssertionSuccess();
  } catch (const CalibrationError& e) {
    const std::string message = e.what();
    if (message.empty()) return ::testing::AssertionFailure() << "an empty message";
    for (const char c : message) {
      if (c < 0x20 || c > 0x7e) {
        return ::testing::AssertionFailure()
               << "byte " << static_cast<int>(static_cast<unsigned char>(c))
               << " in the message: " << message;
      }
    }
    return ::testing::AssertionSuccess();
  } catch (const std::exception& e) {
    return ::testing::AssertionFailure()
           << "threw " << typeid(e).name() << " (" << e.what() << "), not CalibrationError";
  } catch (...) {
    return ::testing::AssertionFailure() << "threw something that is not a std::exception";
  }
}

TEST(ParseProbeCsv, DamagedTextIsReadOrRefusedNeverAnythingElse) {
  const std::string good = probe_csv(two_contacts());
  ASSERT_TRUE(read_or_refused(good));
  // Cut at every byte.
  for (std::size_t n = 0; n <= good.size(); ++n)
    EXPECT_TRUE(read_or_refused(std::string_view(good).substr(0, n))) << "cut at " << n;
  // One to three bytes replaced: by any printable character, by any byte at all, or by one that
  // means something to the format. Raw engine output (not a distribution) gives the same sequence
  // with every standard library.
  const std::string meaningful = ",\n\r\t -+.e0123456789";
  std::mt19937 random(20240611);
  for (int trial = 0; trial < 4000; ++trial) {
    std::string text = good;
    std::string what;
    for (int flips = 1 + static_cast<int>(random() % 3); flips > 0; --flips) {
      const std::size_t at = random() % text.size();
      const std::uint32_t kind = random() % 3;
      const std::uint32_t pick = random();
      text[at] = kind == 0   ? static_cast<char>(0x20 + pick % 95)
                 : kind == 1 ? static_cast<char>(pick % 256)
                             : meaningful[pick % meaningful.size()];
      what += " byte " + std::to_string(at) + " = " +
              std::to_string(static_cast<unsigned char>(text[at]));
    }
    EXPECT_TRUE(read_or_refused(text)) << "trial " << trial << ":" << what;
  }
}

}  // namespace
}  // namespace incise::sim::calibrate
