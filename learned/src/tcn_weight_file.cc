#include "hdvio/learned/tcn_weight_file.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "hdvio/core/error.h"

namespace hdvio::learned {
namespace {

constexpr const char* kFormatName = "hdvio_tcn";
constexpr int kFormatVersion = 1;

// Walks the meaningful lines of the file, splitting each into whitespace tokens.
class LineCursor {
 public:
  LineCursor(const std::string& text, std::string name) : in_(text), name_(std::move(name)) {}

  // Next non-blank, non-comment line; false at end of text.
  bool next() {
    std::string line;
    while (std::getline(in_, line)) {
      ++line_;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      std::istringstream ss(line);
      tokens_.clear();
      for (std::string tok; ss >> tok;) tokens_.push_back(tok);
      if (tokens_.empty() || tokens_[0][0] == '#') continue;
      return true;
    }
    tokens_.clear();
    return false;
  }
  void expectNext(const std::string& what) {
    if (!next()) fail("unexpected end of file, expected " + what);
  }
  const std::vector<std::string>& tokens() const { return tokens_; }
  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(name_, line_, problem);
  }
  long line() const { return line_; }

  void expectTokens(std::size_t n, const std::string& form) const {
    if (tokens_.size() != n) {
      fail("expected \"" + form + "\", found " + std::to_string(tokens_.size()) + " fields");
    }
  }
  long integer(std::size_t i, long lo, long hi) const {
    const std::string& s = tokens_.at(i);
    char* end = nullptr;
    errno = 0;
    const long v = std::strtol(s.c_str(), &end, 10);
    if (errno != 0 || end == s.c_str() || *end != '\0') fail("'" + s + "' is not an integer");
    if (v < lo || v > hi) {
      fail(s + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    return v;
  }
  double real(std::size_t i) const {
    const std::string& s = tokens_.at(i);
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (end == s.c_str() || *end != '\0') fail("'" + s + "' is not a number");
    if (!std::isfinite(v) || std::fabs(v) > 3.0e38) fail("'" + s + "' is not a finite float");
    return v;
  }

 private:
  std::istringstream in_;
  std::string name_;
  long line_ = 0;
  std::vector<std::string> tokens_;
};

long keyValue(LineCursor& c, const std::string& key, long lo, long hi) {
  c.expectNext(key);
  if (c.tokens()[0] != key) c.fail("expected \"" + key + "\", found \"" + c.tokens()[0] + "\"");
  c.expectTokens(2, key + " <value>");
  return c.integer(1, lo, hi);
}

// Reads "<kind> <name> <dims...>" and the numbers below it into a rows x cols matrix.
MatrixXf readTensor(LineCursor& c, const std::string& name, long rows, long cols, bool vector) {
  const std::string kind = vector ? "vector" : "matrix";
  const std::string form = vector ? "vector " + name + " " + std::to_string(rows)
                                  : "matrix " + name + " " + std::to_string(rows) + " " +
                                        std::to_string(cols);
  c.expectNext(form);
  const auto& t = c.tokens();
  if (t[0] != kind || t.size() < 2 || t[1] != name) c.fail("expected \"" + form + "\"");
  c.expectTokens(vector ? 3 : 4, form);
  const long r = c.integer(2, 0, 1 << 20);
  const long k = vector ? 1 : c.integer(3, 0, 1 << 20);
  if (r != rows || k != cols) c.fail("shape of " + name + " does not match: expected \"" + form + "\"");
  MatrixXf m(rows, cols);
  if (vector) {
    c.expectNext(std::to_string(rows) + " numbers of " + name);
    c.expectTokens(static_cast<std::size_t>(rows), std::to_string(rows) + " numbers");
    for (long i = 0; i < rows; ++i) m(i, 0) = static_cast<float>(c.real(i));
  } else {
    for (long i = 0; i < rows; ++i) {
      c.expectNext("row " + std::to_string(i) + " of " + name);
      c.expectTokens(static_cast<std::size_t>(cols), std::to_string(cols) + " numbers");
      for (long j = 0; j < cols; ++j) m(i, j) = static_cast<float>(c.real(j));
    }
  }
  return m;
}

void writeMatrix(std::ostream& os, const std::string& name, const MatrixXf& m) {
  os << "matrix " << name << ' ' << m.rows() << ' ' << m.cols() << '\n';
  char buf[32];
  for (long i = 0; i < m.rows(); ++i) {
    for (long j = 0; j < m.cols(); ++j) {
      std::snprintf(buf, sizeof(buf), "%.9g", static_cast<double>(m(i, j)));
      os << (j ? " " : "") << buf;
    }
    os << '\n';
  }
}

void writeVector(std::ostream& os, const std::string& name, const VectorXf& v) {
  os << "vector " << name << ' ' << v.size() << '\n';
  char buf[32];
  for (long i = 0; i < v.size(); ++i) {
    std::snprintf(buf, sizeof(buf), "%.9g", static_cast<double>(v(i)));
    os << (i ? " " : "") << buf;
  }
  os << '\n';
}

}  // namespace

Tcn parseTcnWeights(const std::string& text, const std::string& name) {
  LineCursor c(text, name);
  c.expectNext("the header \"hdvio_tcn 1\"");
  if (c.tokens()[0] != kFormatName) c.fail("not an hdvio TCN weight file (no \"hdvio_tcn\" header)");
  c.expectTokens(2, "hdvio_tcn <version>");
  if (c.integer(1, 0, 1000) != kFormatVersion) c.fail("unsupported format version " + c.tokens()[1]);

  TcnArchitecture a;
  a.input_channels = static_cast<int>(keyValue(c, "input_channels", 1, 4096));
  a.kernel_size = static_cast<int>(keyValue(c, "kernel_size", 1, 16));
  a.window = static_cast<int>(keyValue(c, "window", 1, 100000));
  c.expectNext("sample_rate_hz");
  if (c.tokens()[0] != "sample_rate_hz") c.fail("expected \"sample_rate_hz <value>\"");
  c.expectTokens(2, "sample_rate_hz <value>");
  a.sample_rate_hz = c.real(1);
  if (a.sample_rate_hz <= 0.0) c.fail("sample_rate_hz must be positive");
  a.variance_head = keyValue(c, "variance_head", 0, 1) == 1;
  const long n_layers = keyValue(c, "layers", 1, 256);
  for (long l = 0; l < n_layers; ++l) {
    c.expectNext("layer <out_channels> <dilation>");
    if (c.tokens()[0] != "layer") c.fail("expected \"layer <out_channels> <dilation>\"");
    c.expectTokens(3, "layer <out_channels> <dilation>");
    a.layers.push_back({static_cast<int>(c.integer(1, 1, 4096)), static_cast<int>(c.integer(2, 1, 4096))});
  }
  const long header_line = c.line();
  try {
    a.validate();
  } catch (const std::invalid_argument& e) {
    throw InputError(name, header_line, std::string("inconsistent architecture: ") + e.what());
  }

  TcnWeights w;
  w.input_mean = readTensor(c, "input_mean", a.input_channels, 1, true);
  w.input_std = readTensor(c, "input_std", a.input_channels, 1, true);
  if (!(w.input_std.array() > 0.0f).all()) c.fail("input_std must be positive");
  long width = a.input_channels;
  for (std::size_t l = 0; l < a.layers.size(); ++l) {
    const std::string p = "conv" + std::to_string(l);
    TcnConvWeights cw;
    cw.weight = readTensor(c, p + ".weight", a.layers[l].out_channels, a.kernel_size * width, false);
    cw.bias = readTensor(c, p + ".bias", a.layers[l].out_channels, 1, true);
    w.conv.push_back(std::move(cw));
    width = a.layers[l].out_channels;
  }
  w.head_weight = readTensor(c, "head.weight", a.output_channels, width, false);
  w.head_bias = readTensor(c, "head.bias", a.output_channels, 1, true);
  if (a.variance_head) {
    w.logvar_weight = readTensor(c, "logvar.weight", a.output_channels, width, false);
    w.logvar_bias = readTensor(c, "logvar.bias", a.output_channels, 1, true);
  }
  c.expectNext("end");
  if (c.tokens().size() != 1 || c.tokens()[0] != "end") c.fail("expected \"end\"");
  if (c.next()) c.fail("unexpected content after \"end\"");
  try {
    return Tcn(std::move(a), std::move(w));
  } catch (const std::invalid_argument& e) {
    throw InputError(name, 0, e.what());
  }
}

Tcn loadTcnWeights(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open the TCN weight file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parseTcnWeights(ss.str(), path);
}

std::string formatTcnWeights(const Tcn& tcn, const std::string& comment) {
  const TcnArchitecture& a = tcn.architecture();
  const TcnWeights& w = tcn.weights();
  std::ostringstream os;
  os << kFormatName << ' ' << kFormatVersion << '\n';
  std::istringstream lines(comment);
  for (std::string line; std::getline(lines, line);) os << "# " << line << '\n';
  char rate[32];
  std::snprintf(rate, sizeof(rate), "%.17g", a.sample_rate_hz);
  os << "input_channels " << a.input_channels << "\nkernel_size " << a.kernel_size
     << "\nwindow " << a.window << "\nsample_rate_hz " << rate << "\nvariance_head "
     << (a.variance_head ? 1 : 0) << "\nlayers " << a.layers.size() << '\n';
  for (const auto& l : a.layers) os << "layer " << l.out_channels << ' ' << l.dilation << '\n';
  writeVector(os, "input_mean", w.input_mean);
  writeVector(os, "input_std", w.input_std);
  for (std::size_t l = 0; l < w.conv.size(); ++l) {
    writeMatrix(os, "conv" + std::to_string(l) + ".weight", w.conv[l].weight);
    writeVector(os, "conv" + std::to_string(l) + ".bias", w.conv[l].bias);
  }
  writeMatrix(os, "head.weight", w.head_weight);
  writeVector(os, "head.bias", w.head_bias);
  if (a.variance_head) {
    writeMatrix(os, "logvar.weight", w.logvar_weight);
    writeVector(os, "logvar.bias", w.logvar_bias);
  }
  os << "end\n";
  return os.str();
}

void saveTcnWeights(const Tcn& tcn, const std::string& path, const std::string& comment) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path, 0, "cannot write the TCN weight file");
    out << formatTcnWeights(tcn, comment);
    if (!out.flush()) throw InputError(path, 0, "failed writing the TCN weight file");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw InputError(path, 0, "cannot move the TCN weight file into place");
  }
}

}  // namespace hdvio::learned
