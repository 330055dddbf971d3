// Reading a run's time series back (time_series_file.hpp).
#include "sim/time_series_file.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>

#include "common/error.hpp"
#include "common/format.hpp"
#include "sim/row_writer.hpp"

namespace pcsim::sim {

namespace fs = std::filesystem;

namespace {

#if !defined(__BYTE_ORDER__) || __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "timeseries.npy is read as little-endian float64 ('<f8'): a big-endian host needs a byte swap"
#endif

constexpr int kMaxLabelBytes = 64;  // a mode label's field ('|S7' for "contact")

bool is_identifier(const std::string& s) {
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
  return std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

// The index of `text` in `labels`, added when new.
double label_index(std::vector<std::string>& labels, const std::string& text) {
  const auto it = std::find(labels.begin(), labels.end(), text);
  if (it != labels.end()) return static_cast<double>(it - labels.begin());
  labels.push_back(text);
  return static_cast<double>(labels.size() - 1);
}

}  // namespace

std::vector<std::string> split_csv_fields(const std::string& line) {
  std::vector<std::string> out;
  std::size_t b = 0;
  while (true) {
    const std::size_t e = line.find(',', b);
    out.push_back(line.substr(b, e == std::string::npos ? std::string::npos : e - b));
    if (e == std::string::npos) break;
    b = e + 1;
  }
  return out;
}

namespace {

// The columns of a time series: 't' first, the labels (mode_ columns) last.
int check_columns(const std::vector<std::string>& header, const std::vector<bool>& is_label,
                  const std::string& file) {
  if (header.empty() || header[0] != "t" || is_label[0])
    throw InputError(file + ": expected a pcsim time series (its first column 't')");
  const auto first_label = std::find(is_label.begin(), is_label.end(), true);
  if (std::find(first_label, is_label.end(), false) != is_label.end())
    throw InputError(file + ": expected the mode_ columns (the contacts' modes) after every "
                     "number column, as pcsim writes them");
  return static_cast<int>(is_label.end() - first_label);
}

TimeSeries read_csv(const fs::path& f, const std::string& text, const std::string& half_written) {
  const std::string file = f.string();
  if (text.empty() || text.back() != '\n')
    throw InputError(file + ": the time series ends in a torn row; " + half_written);
  TimeSeries t;
  t.file = f;
  std::size_t pos = text.find('\n');
  t.header = split_csv_fields(text.substr(0, pos));
  std::vector<bool> is_label;
  for (const auto& h : t.header) is_label.push_back(h.rfind("mode_", 0) == 0);
  t.label_columns = check_columns(t.header, is_label, file);
  const std::size_t numbers = t.header.size() - static_cast<std::size_t>(t.label_columns);
  ++pos;
  std::size_t line_no = 1;
  while (pos < text.size()) {
    const std::size_t e = text.find('\n', pos);
    const auto fields = split_csv_fields(text.substr(pos, e - pos));
    pos = e + 1;
    ++line_no;
    if (fields.size() != t.header.size())
      throw InputError(file + ":" + std::to_string(line_no) + ": expected " +
                       std::to_string(t.header.size()) + " fields, got " + std::to_string(fields.size()) +
                       "; " + half_written);
    for (std::size_t i = 0; i < fields.size(); ++i) {
      if (i >= numbers) {
        t.values.push_back(label_index(t.labels, fields[i]));
        continue;
      }
      if (fields[i].empty()) {  // a value the run has not (fstar in flight): NaN
        t.values.push_back(std::nan(""));
        continue;
      }
      char* end = nullptr;
      t.values.push_back(std::strtod(fields[i].c_str(), &end));
      if (*end != '\0')
        throw InputError(file + ":" + std::to_string(line_no) + ": column '" + t.header[i] +
                         "': expected a number, got '" + fields[i].substr(0, 40) + "'");
    }
  }
  if (t.values.empty()) throw InputError(file + ": the time series has no rows; " + half_written);
  return t;
}

// The header dictionary of a .npy file, a Python literal, read as far as pcsim writes it:
// single-quoted strings, a list of (name, type) pairs, False/True, a tuple of integers.
class NpyDict {
 public:
  NpyDict(std::string text, std::string file) : s_(std::move(text)), file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(file_ + ": not a time series as pcsim writes it: " + what);
  }
  void space() {
    while (i_ < s_.size() && s_[i_] == ' ') ++i_;
  }
  bool take(char c) {
    space();
    if (i_ < s_.size() && s_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  void expect(char c, const std::string& where) {
    if (!take(c)) fail(std::string("expected '") + c + "' " + where + " in the header " + context());
  }
  std::string string(const std::string& where) {
    space();
    if (i_ >= s_.size() || s_[i_] != '\'') fail("expected a quoted string " + where + " in the header " + context());
    std::string out;
    for (++i_; i_ < s_.size() && s_[i_] != '\''; ++i_) {
      if (s_[i_] == '\\') ++i_;  // \' and \\ (the writer escapes both)
      if (i_ >= s_.size()) break;
      const unsigned char c = static_cast<unsigned char>(s_[i_]);
      if (c < 0x20 || c > 0x7e) fail("expected printable ASCII " + where + " in the header");
      out += s_[i_];
    }
    if (i_ >= s_.size()) fail("a string " + where + " in the header has no closing quote");
    ++i_;
    return out;
  }
  bool boolean(const std::string& where) {
    space();
    for (const char* word : {"False", "True"})
      if (s_.compare(i_, std::strlen(word), word) == 0) {
        i_ += std::strlen(word);
        return word[0] == 'T';
      }
    fail("expected False or True " + where + " in the header " + context());
  }
  std::uint64_t integer(const std::string& where) {
    space();
    if (i_ >= s_.size() || !std::isdigit(static_cast<unsigned char>(s_[i_])))
      fail("expected a non-negative integer " + where + " in the header " + context());
    std::uint64_t v = 0;
    for (; i_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[i_])); ++i_) {
      const unsigned d = static_cast<unsigned>(s_[i_] - '0');
      if (v > (std::numeric_limits<std::uint64_t>::max() - d) / 10)
        fail("the integer " + where + " in the header exceeds 2^64");
      v = v * 10 + d;
    }
    return v;
  }
  bool at_end() {
    space();
    return i_ == s_.size();
  }

 private:
  std::string context() const {
    const std::size_t b = std::min(i_, s_.size());
    std::string near = s_.substr(b, 24);
    for (char& c : near)
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e) c = '?';
    return "(at byte " + std::to_string(b) + ": '" + near + "')";
  }

  std::string s_;
  std::string file_;
  std::size_t i_ = 0;
};

std::uint64_t little_endian(const std::string& bytes, std::size_t at, int n) {
  std::uint64_t v = 0;
  for (int k = n - 1; k >= 0; --k) v = v << 8 | static_cast<unsigned char>(bytes[at + static_cast<std::size_t>(k)]);
  return v;
}

void read_descr(NpyDict& d, NpyLayout& out) {
  if (!d.take('['))
    d.fail("expected 'descr' to be a list of named fields (the CSV's columns); a plain array "
           "has no column names");
  do {
    if (d.take(']')) return;  // after a trailing comma
    d.expect('(', "opening a field of 'descr'");
    const std::string name = d.string("naming a field");
    if (!is_identifier(name)) d.fail("expected a column name (letters, digits, '_'), got the field '" + name + "'");
    if (std::find(out.names.begin(), out.names.end(), name) != out.names.end())
      d.fail("the field '" + name + "' appears twice");
    d.expect(',', "after the field name '" + name + "'");
    const std::string type = d.string("as the type of '" + name + "'");
    int width = 0;
    if (type.rfind("|S", 0) == 0 && type.size() > 2 && type.size() <= 4 &&
        std::all_of(type.begin() + 2, type.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); }))
      width = std::atoi(type.c_str() + 2);
    if (type != "<f8" && !(width >= 1 && width <= kMaxLabelBytes))
      d.fail("field '" + name + "': expected the type '<f8' (little-endian float64) or a label '|Sn' "
             "(n from 1 to " + std::to_string(kMaxLabelBytes) + "), got '" + type + "'");
    if (width == 0 && !out.widths.empty() && out.widths.back() > 0)
      d.fail("field '" + name + "': expected the numbers before the labels");
    d.expect(')', "closing the field '" + name + "'");
    out.names.push_back(name);
    out.widths.push_back(width);
    out.record_bytes += width ? static_cast<std::uint64_t>(width) : 8u;
  } while (d.take(','));
  d.expect(']', "closing 'descr'");
}

}  // namespace

fs::path time_series_file(const fs::path& dir) {
  std::error_code ec;
  const fs::path csv = dir / "timeseries.csv", npy = dir / "timeseries.npy";
  return !fs::exists(csv, ec) && fs::exists(npy, ec) ? npy : csv;
}

std::string read_run_file(const fs::path& f, std::uint64_t limit, const std::string& what) {
  std::error_code ec;
  if (!fs::is_regular_file(f, ec))
    throw InputError(f.string() + ": expected " + what + " (a regular file)");
  const auto size = fs::file_size(f, ec);
  if (ec || size > limit)
    throw InputError(f.string() + ": expected " + what + " of at most " + format_number(double(limit)) + " bytes");
  std::ifstream in(f, std::ios::binary);
  std::string text(static_cast<std::size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  if (!in || static_cast<std::uint64_t>(in.gcount()) != size) throw InputError(f.string() + ": cannot read " + what);
  return text;
}

NpyLayout read_npy_layout(const std::string& bytes, const std::string& file, const std::string& half_written) {
  NpyLayout out;
  auto fail = [&](const std::string& what) { throw InputError(file + ": " + what); };
  const std::string magic = "\x93NUMPY";
  const std::size_t m = std::min(bytes.size(), magic.size());
  if (bytes.compare(0, m, magic, 0, m) != 0) fail("not a NumPy .npy file (expected the magic string \\x93NUMPY)");
  if (bytes.size() < 10) fail("cut off within its first 10 bytes (a NumPy .npy file); " + half_written);
  const int major = static_cast<unsigned char>(bytes[6]), minor = static_cast<unsigned char>(bytes[7]);
  if ((major != 1 && major != 2) || minor != 0)
    fail("expected .npy format version 1.0 or 2.0, got " + std::to_string(major) + "." + std::to_string(minor));
  const std::size_t prefix = major == 1 ? 10 : 12;
  if (bytes.size() < prefix) fail("cut off within its header's length; " + half_written);
  const std::uint64_t length = little_endian(bytes, 8, major == 1 ? 2 : 4);
  if (length > bytes.size() - prefix)
    fail("its header of " + std::to_string(length) + " bytes is cut off after " +
         std::to_string(bytes.size() - prefix) + "; " + half_written);
  if (length == 0 || bytes[prefix + length - 1] != '\n') fail("expected its header to end in a line break");
  out.data_offset = prefix + length;
  NpyDict d(bytes.substr(prefix, length - 1), file);
  bool have_descr = false, have_order = false, have_shape = false;
  d.expect('{', "opening");
  bool closed = d.take('}');
  while (!closed) {
    const std::string key = d.string("as a key");
    d.expect(':', "after '" + key + "'");
    bool* seen = key == "descr" ? &have_descr : key == "fortran_order" ? &have_order : key == "shape" ? &have_shape : nullptr;
    if (!seen) d.fail("unexpected key '" + key + "' (expected 'descr', 'fortran_order' and 'shape')");
    if (*seen) d.fail("the key '" + key + "' appears twice");
    *seen = true;
    if (key == "descr") {
      read_descr(d, out);
    } else if (key == "fortran_order") {
      if (d.boolean("for 'fortran_order'")) d.fail("expected 'fortran_order': False (rows in C order), got True");
    } else {
      d.expect('(', "opening 'shape'");
      out.rows = d.integer("in 'shape'");
      if (!d.take(',') || !d.take(')'))
        d.fail("expected 'shape' to be one dimension (rows,) of records");
    }
    if (!d.take(',')) {
      d.expect('}', "closing the dictionary");
      closed = true;
    } else {
      closed = d.take('}');  // after a trailing comma
    }
  }
  if (!d.at_end()) d.fail("expected only spaces after the header's '}'");
  if (!have_descr || !have_order || !have_shape)
    d.fail(std::string("expected the keys 'descr', 'fortran_order' and 'shape'; '") +
           (!have_descr ? "descr" : !have_order ? "fortran_order" : "shape") + "' is missing");
  if (out.names.empty()) d.fail("expected at least one field in 'descr'");
  const std::uint64_t data = bytes.size() - out.data_offset;
  if (out.rows > data / out.record_bytes || out.rows * out.record_bytes != data)
    fail("its header says " + std::to_string(out.rows) + " rows of " + std::to_string(out.record_bytes) +
         " bytes, the file holds " + std::to_string(data) + " bytes after the header; " + half_written);
  if (out.rows == 0) fail("the time series has no rows; " + half_written);
  return out;
}

TimeSeries read_time_series(const fs::path& f, std::uint64_t max_bytes, const std::string& half_written) {
  const bool npy = f.extension() == ".npy";
  const std::string bytes = read_run_file(f, max_bytes, "a pcsim time series");
  if (!npy) return read_csv(f, bytes, half_written);
  const std::string file = f.string();
  const NpyLayout layout = read_npy_layout(bytes, file, half_written);
  TimeSeries t;
  t.file = f;
  t.header = layout.names;
  std::vector<bool> is_label;
  for (int w : layout.widths) is_label.push_back(w > 0);
  t.label_columns = check_columns(t.header, is_label, file);
  const std::size_t columns = t.header.size(), rows = static_cast<std::size_t>(layout.rows);
  t.values.resize(rows * columns);
  const char* p = bytes.data() + layout.data_offset;
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < columns; ++c) {
      const int w = layout.widths[c];
      double& v = t.values[r * columns + c];
      if (w == 0) {
        std::memcpy(&v, p, sizeof v);  // the number's 8 bytes as written
        p += sizeof v;
        continue;
      }
      // A label: its text, then zeros to the field's width.
      const std::string field(p, static_cast<std::size_t>(w));
      p += w;
      const std::size_t n = field.find('\0');
      const std::string text = field.substr(0, n);
      const bool padded = n == std::string::npos || field.find_first_not_of('\0', n) == std::string::npos;
      if (text.empty() || !padded || !std::all_of(text.begin(), text.end(), [](char ch) {
            return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_';
          }))
        throw InputError(file + ": row " + std::to_string(r + 1) + ", column '" + t.header[c] +
                         "': expected a mode (letters, digits, '_') padded with zero bytes to " +
                         std::to_string(w) + " bytes");
      v = label_index(t.labels, text);
    }
  return t;
}

std::string time_series_csv(const TimeSeries& series) {
  const int columns = static_cast<int>(series.header.size());
  std::string text = csv_header_line(series.header);
  std::vector<char> line(csv_row_room(columns, series.label_columns, series.labels));
  for (std::size_t r = 0; r < series.rows(); ++r)
    text.append(line.data(), write_csv_row(line.data(), &series.values[r * series.header.size()], columns,
                                           series.label_columns, series.labels));
  return text;
}

}  // namespace pcsim::sim
