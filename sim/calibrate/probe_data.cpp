#include "sim/calibrate/probe_data.h"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <sstream>

namespace incise::sim::calibrate {
namespace {

constexpr std::array<std::string_view, 9> kColumns = {"time_s", "contact", "x",     "y",      "z",
                                                      "dir_x",  "dir_y",   "dir_z", "force_n"};
enum Column { kTime, kContact, kX, kY, kZ, kDirX, kDirY, kDirZ, kForce };

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t'))
    s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma - start)));
    if (comma == std::string_view::npos) return fields;
    start = comma + 1;
  }
}

std::optional<Real> number(std::string_view text) {
  Real value = 0;
  if (text.size() > 1 && text.front() == '+' && text[1] != '-' && text[1] != '+') {
    text.remove_prefix(1);
  }
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

// At most 40 characters of what the file holds, for a message.
std::string quoted(std::string_view text) {
  std::string out(text.substr(0, 40));
  for (char& c : out) {
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
  }
  return "'" + out + (text.size() > 40 ? "...'" : "'");
}

std::string fixed(Real value) {
  std::ostringstream s;
  s.precision(10);
  s << value;
  return s.str();
}

}  // namespace

ProbeData parse_probe_csv(std::string_view text) {
  // A spreadsheet's UTF-8 byte-order mark is not part of the first column's name.
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
  std::array<int, kColumns.size()> where{};
  where.fill(-1);
  std::size_t fields_per_row = 0;
  bool header = false;
  std::map<int, ProbeContact> contacts;
  int line_number = 0;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = trim(text.substr(start, end - start));
    start = end + 1;
    ++line_number;
    for (const char c : line) {
      if (static_cast<unsigned char>(c) < 0x20 && c != '\t') {
        char byte[8];
        std::snprintf(byte, sizeof byte, "0x%02x",
                      static_cast<unsigned>(static_cast<unsigned char>(c)));
        throw CalibrationError("line " + std::to_string(line_number) +
                               ": a control character (byte " + byte + ")");
      }
    }
    if (line.empty()) continue;
    const std::vector<std::string_view> fields = split(line);
    if (!header) {
      for (std::size_t i = 0; i < fields.size(); ++i) {
        for (std::size_t c = 0; c < kColumns.size(); ++c) {
          if (fields[i] != kColumns[c]) continue;
          if (where[c] >= 0) {
            throw CalibrationError("line " + std::to_string(line_number) + ": column " +
                                   std::string(kColumns[c]) + " appears twice");
          }
          where[c] = static_cast<int>(i);
        }
      }
      std::string missing;
      for (std::size_t c = 0; c < kColumns.size(); ++c) {
        if (where[c] < 0) missing += (missing.empty() ? "" : ", ") + std::string(kColumns[c]);
      }
      if (!missing.empty()) {
        throw CalibrationError("line " + std::to_string(line_number) + ": missing column" +
                               (missing.find(',') != std::string::npos ? "s " : " ") + missing +
                               " (the header needs time_s, contact, x, y, z, dir_x, dir_y, "
                               "dir_z, force_n)");
      }
      fields_per_row = fields.size();
      header = true;
      continue;
    }
    const std::string at = "line " + std::to_string(line_number) + ": ";
    if (fields.size() != fields_per_row) {
      throw CalibrationError(at + std::to_string(fields.size()) + " values, the header has " +
                             std::to_string(fields_per_row));
    }
    std::array<Real, kColumns.size()> v{};
    for (std::size_t c = 0; c < kColumns.size(); ++c) {
      const std::string_view field = fields[static_cast<std::size_t>(where[c])];
      const std::optional<Real> value = number(field);
      if (!value) {
        throw CalibrationError(at + std::string(kColumns[c]) + " " + quoted(field) +
                               " is not a number");
      }
      v[c] = *value;
    }
    if (v[kContact] != std::floor(v[kContact]) || std::abs(v[kContact]) > 1e6) {
      throw CalibrationError(at + "contact " +
                             quoted(fields[static_cast<std::size_t>(where[kContact])]) +
                             " is not a whole number");
    }
    ProbeSample sample;
    sample.time = v[kTime];
    sample.position = {v[kX], v[kY], v[kZ]};
    // Scaled by its largest component first, so that no norm overflows or underflows.
    Vec3 direction(v[kDirX], v[kDirY], v[kDirZ]);
    const Real largest = direction.cwiseAbs().maxCoeff();
    if (!(largest > 0)) throw CalibrationError(at + "the direction is zero");
    direction /= largest;
    sample.direction = direction.normalized();
    if (v[kForce] < 0) {
      throw CalibrationError(at + "force_n " + fixed(v[kForce]) +
                             " is negative (the probe pushes along dir)");
    }
    sample.force = v[kForce];
    const int id = static_cast<int>(v[kContact]);
    ProbeContact& contact = contacts[id];
    contact.id = id;
    if (!contact.samples.empty() && !(sample.time > contact.samples.back().time)) {
      throw CalibrationError(at + "time_s " + fixed(sample.time) + " of contact " +
                             std::to_string(id) + " is not after " +
                             fixed(contact.samples.back().time));
    }
    contact.samples.push_back(sample);
  }
  if (!header) throw CalibrationError("the file is empty (no header line)");
  if (contacts.empty()) throw CalibrationError("no samples after the header");

  ProbeData data;
  for (auto& [id, contact] : contacts) {
    const std::string which = "contact " + std::to_string(id) + ": ";
    const auto n = static_cast<int>(contact.samples.size());
    if (n < kMinSamplesPerContact) {
      throw CalibrationError(which + std::to_string(n) + " sample" + (n == 1 ? "" : "s") +
                             ", at least " + std::to_string(kMinSamplesPerContact) + " needed");
    }
    bool pushed = false;
    for (const ProbeSample& s : contact.samples)
      pushed = pushed || s.force > 0;
    if (!pushed) throw CalibrationError(which + "no contact: every force_n is 0");
    for (int k = 1; k < n; ++k) {
      const Real step = contact.samples[k].time - contact.samples[k - 1].time;
      if (data.step == 0) {
        if (!(step >= kMinStep && step <= kMaxStep)) {
          throw CalibrationError(which + "samples " + fixed(step) +
                                 " s apart: the step must be from 1 us to 10 s");
        }
        data.step = step;
      }
      if (std::abs(step - data.step) > kStepTolerance * data.step) {
        throw CalibrationError(which + "samples " + fixed(step) + " s apart at time_s " +
                               fixed(contact.samples[k].time) + ", the data's step is " +
                               fixed(data.step) + " s (samples must be evenly spaced)");
      }
    }
    data.contacts.push_back(std::move(contact));
  }
  return data;
}

std::string probe_csv(const ProbeData& data) {
  std::string out = "time_s,contact,x,y,z,dir_x,dir_y,dir_z,force_n\n";
  char buffer[64];
  const auto append = [&](Real value, char after) {
    if (value == 0) value = 0;  // no "-0"
    const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
    out.append(buffer, end);
    out += after;
  };
  for (const ProbeContact& contact : data.contacts) {
    for (const ProbeSample& s : contact.samples) {
      append(s.time, ',');
      out += std::to_string(contact.id) + ',';
      for (int i = 0; i < 3; ++i)
        append(s.position[i], ',');
      for (int i = 0; i < 3; ++i)
        append(s.direction[i], ',');
      append(s.force, '\n');
    }
  }
  return out;
}

}  // namespace incise::sim::calibrate
