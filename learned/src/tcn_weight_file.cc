#include "hdvio/learned/tcn_weight_file.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "hdvio/core/error.h"

namespace hdvio::learned {
namespace {

constexpr const char* kFormatName = "hdvio_tcn";
constexpr int kFormatVersion = 1;   // plain networks, no info
constexpr int kFormatVersion2 = 2;  // residual networks, info, float32 encoding
constexpr int kFormatVersion3 = 3;  // version 2 + the drag law the force network complements
constexpr int kFormatVersion4 = 4;  // version 3 + sample_times, block_relu, window_padding
constexpr int kFormatVersion5 = 5;  // version 4 + force_walk
constexpr int kFormatVersion6 = 6;  // version 5 + supervision
constexpr int kFormatVersion7 = 7;  // version 6 + training envelope

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
  // The next n raw bytes (binary tensor data); false if the text ends first.
  bool rawBytes(std::size_t n, std::string* out) {
    // The count comes from the file: allocate only what the text can still hold.
    const std::streamsize left = in_.rdbuf()->in_avail();
    if (left < 0 || static_cast<std::size_t>(left) < n) return false;
    out->resize(n);
    in_.read(out->data(), static_cast<std::streamsize>(n));
    return static_cast<std::size_t>(in_.gcount()) == n;
  }

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
    // Up to the largest float as the writer prints it (%.9g), so every float the float32
    // encoding holds can be written as text and read back.
    if (!std::isfinite(v) || std::fabs(v) > 3.40282347e38) fail("'" + s + "' is not a finite float");
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


// Tensors in file order; the text and float32 encodings read them through this interface.
class TensorReader {
 public:
  virtual ~TensorReader() = default;
  virtual MatrixXf read(const std::string& name, long rows, long cols, bool vector) = 0;
};

class TextTensorReader : public TensorReader {
 public:
  explicit TextTensorReader(LineCursor& c) : c_(c) {}
  MatrixXf read(const std::string& name, long rows, long cols, bool vector) override {
    return readTensor(c_, name, rows, cols, vector);
  }

 private:
  LineCursor& c_;
};

class Float32TensorReader : public TensorReader {
 public:
  Float32TensorReader(LineCursor& c, std::string bytes) : c_(c), bytes_(std::move(bytes)) {}
  MatrixXf read(const std::string& name, long rows, long cols, bool) override {
    const std::size_t n = static_cast<std::size_t>(rows * cols);
    if (offset_ + 4 * n > bytes_.size()) c_.fail("float32 data too short for " + name);
    MatrixXf m(rows, cols);
    for (long i = 0; i < rows; ++i) {
      for (long j = 0; j < cols; ++j) {
        float v;
        std::memcpy(&v, bytes_.data() + offset_, 4);
        offset_ += 4;
        if (!std::isfinite(v)) c_.fail(name + " holds a non-finite float");
        m(i, j) = v;
      }
    }
    return m;
  }
  bool exhausted() const { return offset_ == bytes_.size(); }

 private:
  LineCursor& c_;
  std::string bytes_;
  std::size_t offset_ = 0;
};

TcnWeights readWeights(LineCursor& c, TensorReader& r, const TcnArchitecture& a) {
  TcnWeights w;
  w.input_mean = r.read("input_mean", a.input_channels, 1, true);
  w.input_std = r.read("input_std", a.input_channels, 1, true);
  if (!(w.input_std.array() > 0.0f).all()) c.fail("input_std must be positive");
  long width = a.input_channels;
  int conv = 0;
  for (std::size_t l = 0; l < a.layers.size(); ++l) {
    const long out = a.layers[l].out_channels;
    for (int j = 0; j < (a.residual ? 2 : 1); ++j, ++conv) {
      const std::string p = "conv" + std::to_string(conv);
      const long in = j == 0 ? width : out;
      TcnConvWeights cw;
      cw.weight = r.read(p + ".weight", out, a.kernel_size * in, false);
      cw.bias = r.read(p + ".bias", out, 1, true);
      w.conv.push_back(std::move(cw));
    }
    if (a.residual) {
      TcnConvWeights sk;
      if (width != out) {
        const std::string p = "skip" + std::to_string(l);
        sk.weight = r.read(p + ".weight", out, width, false);
        sk.bias = r.read(p + ".bias", out, 1, true);
      }
      w.skip.push_back(std::move(sk));
    }
    width = out;
  }
  w.head_weight = r.read("head.weight", a.output_channels, width, false);
  w.head_bias = r.read("head.bias", a.output_channels, 1, true);
  if (a.variance_head) {
    w.logvar_weight = r.read("logvar.weight", a.output_channels, width, false);
    w.logvar_bias = r.read("logvar.bias", a.output_channels, 1, true);
  }
  return w;
}

std::string word(LineCursor& c, const std::string& key, const std::vector<std::string>& allowed) {
  c.expectNext(key);
  if (c.tokens()[0] != key) c.fail("expected \"" + key + " <value>\", found \"" + c.tokens()[0] + "\"");
  c.expectTokens(2, key + " <value>");
  for (const auto& a : allowed) {
    if (c.tokens()[1] == a) return a;
  }
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
  c.fail("unknown " + key + " '" + c.tokens()[1] + "' (expected one of: " + list + ")");
}

TcnFileInfo readInfo(LineCursor& c, bool with_drag_law, bool with_sample_times, bool with_force_walk,
                     bool with_supervision, bool with_envelope) {
  TcnFileInfo info;
  info.task = word(c, "task", {"force", "displacement"});
  info.inputs = word(c, "inputs", {"thrust_gyro", "accel_gyro"});
  c.expectNext("output_sigma");
  if (c.tokens()[0] != "output_sigma") c.fail("expected \"output_sigma <s1> <s2> <s3>\" or \"output_sigma none\"");
  if (!(c.tokens().size() == 2 && c.tokens()[1] == "none")) {
    c.expectTokens(4, "output_sigma <s1> <s2> <s3>");
    for (std::size_t i = 1; i < 4; ++i) {
      info.output_sigma.push_back(c.real(i));
      if (info.output_sigma.back() <= 0.0) c.fail("output_sigma must be positive");
    }
  }
  if (!with_drag_law) return info;
  const std::string form =
      "drag_law <dx> <dy> <dz> <cx> <cy> <cz> [<rx> <ry> <rz> <lift> <sx> <sy> <sz> "
      "[<speed x y z> <rate x y z> <thrust x y z>]]";
  c.expectNext(form);
  if (c.tokens()[0] != "drag_law") c.fail("expected \"" + form + "\" or \"drag_law none\"");
  if (!(c.tokens().size() == 2 && c.tokens()[1] == "none")) {
    // Rotor, lift and sigma are optional, and so is the sigma's growth with speed, rate, thrust.
    const std::size_t n = c.tokens().size();
    if (n != 7 && n != 14 && n != 23) c.expectTokens(7, form);
    DragLaw& d = info.drag_law;
    for (int i = 0; i < 3; ++i) {
      d.linear(i) = c.real(1 + i);
      d.quadratic(i) = c.real(4 + i);
      if (n >= 14) d.rotor(i) = c.real(7 + i), d.sigma(i) = c.real(11 + i);
      if (n == 23)
        d.sigma_speed(i) = c.real(14 + i), d.sigma_rate(i) = c.real(17 + i), d.sigma_thrust(i) = c.real(20 + i);
    }
    if (n >= 14) d.lift = c.real(10);
    const auto negative = [](const Vec3& v) { return (v.array() < 0.0).any(); };
    if (negative(d.linear) || negative(d.quadratic) || negative(d.rotor) || d.lift < 0.0 || negative(d.sigma) ||
        negative(d.sigma_speed) || negative(d.sigma_rate) || negative(d.sigma_thrust))
      c.fail("drag_law coefficients must be non-negative");
  }
  if (with_sample_times) info.sample_times = word(c, "sample_times", {"end", "begin"});
  if (with_force_walk) {
    c.expectNext("force_walk");
    if (c.tokens()[0] != "force_walk") c.fail("expected \"force_walk <m/s^2/sqrt(s)>\"");
    c.expectTokens(2, "force_walk <m/s^2/sqrt(s)>");
    info.force_walk = c.real(1);
    if (info.force_walk < 0.0) c.fail("force_walk must be non-negative");
  }
  if (with_supervision) info.supervision = word(c, "supervision", {"groundtruth", "estimate"});
  if (with_envelope) {
    const std::string form = "envelope <speed_max> <rate_max> <thrust_min> <thrust_max>";
    c.expectNext(form);
    if (c.tokens()[0] != "envelope") c.fail("expected \"" + form + "\"");
    c.expectTokens(5, form);
    ModelEnvelope& e = info.envelope;
    e.speed_max = c.real(1);
    e.rate_max = c.real(2);
    e.thrust_min = c.real(3);
    e.thrust_max = c.real(4);
    if (!(e.speed_max > 0.0 && e.rate_max > 0.0 && e.thrust_min >= 0.0 && e.thrust_max > e.thrust_min))
      c.fail("envelope needs positive speed_max and rate_max and 0 <= thrust_min < thrust_max");
  }
  return info;
}

void writeFloat32(std::ostream& os, const MatrixXf& m) {
  for (long i = 0; i < m.rows(); ++i) {
    for (long j = 0; j < m.cols(); ++j) {
      const float v = m(i, j);
      char b[4];
      std::memcpy(b, &v, 4);
      os.write(b, 4);
    }
  }
}

// Every tensor in file order with its name (the writer's view of readWeights).
std::vector<std::pair<std::string, const MatrixXf*>> tensorsInOrder(const Tcn& tcn,
                                                                    std::deque<MatrixXf>* hold) {
  const TcnArchitecture& a = tcn.architecture();
  const TcnWeights& w = tcn.weights();
  std::vector<std::pair<std::string, const MatrixXf*>> t;
  auto vec = [&](const std::string& n, const VectorXf& v) {
    hold->push_back(v);
    t.push_back({"vector " + n, &hold->back()});
  };
  auto mat = [&](const std::string& n, const MatrixXf& m) { t.push_back({"matrix " + n, &m}); };
  vec("input_mean", w.input_mean);
  vec("input_std", w.input_std);
  const int per_block = a.residual ? 2 : 1;
  for (std::size_t l = 0; l < a.layers.size(); ++l) {
    for (int j = 0; j < per_block; ++j) {
      const std::size_t c = l * per_block + j;
      mat("conv" + std::to_string(c) + ".weight", w.conv[c].weight);
      vec("conv" + std::to_string(c) + ".bias", w.conv[c].bias);
    }
    if (a.residual && w.skip[l].weight.size() > 0) {
      mat("skip" + std::to_string(l) + ".weight", w.skip[l].weight);
      vec("skip" + std::to_string(l) + ".bias", w.skip[l].bias);
    }
  }
  mat("head.weight", w.head_weight);
  vec("head.bias", w.head_bias);
  if (a.variance_head) {
    mat("logvar.weight", w.logvar_weight);
    vec("logvar.bias", w.logvar_bias);
  }
  return t;
}

void writeAtomically(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path, 0, "cannot write the TCN weight file");
    out << content;
    if (!out.flush()) throw InputError(path, 0, "failed writing the TCN weight file");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw InputError(path, 0, "cannot move the TCN weight file into place");
  }
}

}  // namespace

TcnFile parseTcnFile(const std::string& text, const std::string& name) {
  LineCursor c(text, name);
  c.expectNext("the header \"hdvio_tcn <version>\"");
  if (c.tokens()[0] != kFormatName) c.fail("not an hdvio TCN weight file (no \"hdvio_tcn\" header)");
  c.expectTokens(2, "hdvio_tcn <version>");
  const long version = c.integer(1, 0, 1000);
  if (version < kFormatVersion || version > kFormatVersion7) {
    c.fail("unsupported format version " + c.tokens()[1]);
  }
  const bool v2 = version >= kFormatVersion2;  // the version-2 layout (3 adds the drag law)
  TcnFileInfo info;
  const bool v4 = version >= kFormatVersion4;
  if (v2)
    info = readInfo(c, version >= kFormatVersion3, v4, version >= kFormatVersion5,
                    version >= kFormatVersion6, version >= kFormatVersion7);

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
  if (v2) a.residual = keyValue(c, "residual", 0, 1) == 1;
  if (v4) {
    a.block_relu = keyValue(c, "block_relu", 0, 1) == 1;
    a.window_padding = keyValue(c, "window_padding", 0, 1) == 1;
  }
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

  const std::string encoding = v2 ? word(c, "encoding", {"text", "float32"}) : "text";
  TcnWeights w;
  if (encoding == "text") {
    TextTensorReader reader(c);
    w = readWeights(c, reader, a);
  } else {
    const long count = keyValue(c, "data", 0, 1L << 28);
    std::string bytes;
    if (!c.rawBytes(static_cast<std::size_t>(count) * 4, &bytes)) {
      c.fail("unexpected end of file inside the float32 data");
    }
    Float32TensorReader reader(c, std::move(bytes));
    w = readWeights(c, reader, a);
    if (!reader.exhausted()) c.fail("float32 data count does not match the architecture");
  }
  c.expectNext("end");
  if (c.tokens().size() != 1 || c.tokens()[0] != "end") c.fail("expected \"end\"");
  if (c.next()) c.fail("unexpected content after \"end\"");
  try {
    return TcnFile{Tcn(std::move(a), std::move(w)), std::move(info)};
  } catch (const std::invalid_argument& e) {
    throw InputError(name, 0, e.what());
  }
}

Tcn parseTcnWeights(const std::string& text, const std::string& name) {
  return parseTcnFile(text, name).tcn;
}

TcnFile loadTcnFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open the TCN weight file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parseTcnFile(ss.str(), path);
}

Tcn loadTcnWeights(const std::string& path) { return loadTcnFile(path).tcn; }

namespace {

std::string formatAny(const Tcn& tcn, const TcnFileInfo* info, const std::string& comment,
                      TcnEncoding encoding) {
  const TcnArchitecture& a = tcn.architecture();
  std::ostringstream os;
  // The oldest version that can hold what is written (older readers keep working).
  const bool v7 = info && !info->envelope.unbounded();
  const bool v6 = v7 || (info && info->supervision != "groundtruth");
  const bool v5 = v6 || (info && info->force_walk > 0.0);
  const bool v4 = v5 || (info && (a.block_relu || a.window_padding || info->sample_times != "end"));
  const bool with_drag_law = info && (info->drag_law.enabled() || v4);
  os << kFormatName << ' '
     << (v7 ? kFormatVersion7 : v6 ? kFormatVersion6 : v5 ? kFormatVersion5 : v4 ? kFormatVersion4 : with_drag_law ? kFormatVersion3 : info ? kFormatVersion2 : kFormatVersion)
     << '\n';
  std::istringstream lines(comment);
  for (std::string line; std::getline(lines, line);) os << "# " << line << '\n';
  if (info) {
    os << "task " << info->task << "\ninputs " << info->inputs << "\noutput_sigma";
    if (info->output_sigma.empty()) os << " none";
    char buf[32];
    for (double v : info->output_sigma) {
      std::snprintf(buf, sizeof(buf), "%.9g", v);
      os << ' ' << buf;
    }
    os << '\n';
    if (with_drag_law && !info->drag_law.enabled()) {
      os << "drag_law none\n";
    } else if (with_drag_law) {
      // Rotor, lift and sigma only when used: files without them stay as version 3 began.
      const DragLaw& d = info->drag_law;
      std::vector<double> c{d.linear.x(), d.linear.y(), d.linear.z(), d.quadratic.x(), d.quadratic.y(),
                            d.quadratic.z()};
      if (!d.rotor.isZero(0.0) || d.lift != 0.0 || d.hasSigma())
        c.insert(c.end(), {d.rotor.x(), d.rotor.y(), d.rotor.z(), d.lift, d.sigma.x(), d.sigma.y(), d.sigma.z()});
      if (d.hasVaryingSigma())
        for (const Vec3* v : {&d.sigma_speed, &d.sigma_rate, &d.sigma_thrust}) c.insert(c.end(), {v->x(), v->y(), v->z()});
      os << "drag_law";
      for (double v : c) {
        std::snprintf(buf, sizeof(buf), "%.9g", v);
        os << ' ' << buf;
      }
      os << '\n';
    }
    if (v4) os << "sample_times " << info->sample_times << '\n';
    if (v5) {
      std::snprintf(buf, sizeof(buf), "%.9g", info->force_walk);
      os << "force_walk " << buf << '\n';
    }
    if (v6) os << "supervision " << info->supervision << '\n';
    if (v7) {
      const ModelEnvelope& e = info->envelope;
      if (!std::isfinite(e.speed_max) || !std::isfinite(e.rate_max) || !std::isfinite(e.thrust_max))
        throw std::invalid_argument("a weight file's envelope bounds speed, rate and thrust (all four numbers)");
      os << "envelope";
      for (double v : {e.speed_max, e.rate_max, e.thrust_min, e.thrust_max}) {
        std::snprintf(buf, sizeof(buf), "%.9g", v);
        os << ' ' << buf;
      }
      os << '\n';
    }
  }
  char rate[32];
  std::snprintf(rate, sizeof(rate), "%.17g", a.sample_rate_hz);
  os << "input_channels " << a.input_channels << "\nkernel_size " << a.kernel_size
     << "\nwindow " << a.window << "\nsample_rate_hz " << rate << "\nvariance_head "
     << (a.variance_head ? 1 : 0) << '\n';
  if (info) os << "residual " << (a.residual ? 1 : 0) << '\n';
  if (v4) os << "block_relu " << (a.block_relu ? 1 : 0) << "\nwindow_padding " << (a.window_padding ? 1 : 0) << '\n';
  os << "layers " << a.layers.size() << '\n';
  for (const auto& l : a.layers) os << "layer " << l.out_channels << ' ' << l.dilation << '\n';
  std::deque<MatrixXf> hold;  // vectors as matrices; deque keeps their addresses
  const auto tensors = tensorsInOrder(tcn, &hold);
  if (info) os << "encoding " << (encoding == TcnEncoding::kText ? "text" : "float32") << '\n';
  if (encoding == TcnEncoding::kText) {
    for (const auto& [kind_name, m] : tensors) {
      const std::string name = kind_name.substr(7);
      if (kind_name[0] == 'v') {
        writeVector(os, name, *m);
      } else {
        writeMatrix(os, name, *m);
      }
    }
  } else {
    long count = 0;
    for (const auto& t : tensors) count += t.second->size();
    os << "data " << count << '\n';
    for (const auto& t : tensors) writeFloat32(os, *t.second);
    os << '\n';
  }
  os << "end\n";
  return os.str();
}

}  // namespace

std::string formatTcnFile(const Tcn& tcn, const TcnFileInfo& info, const std::string& comment,
                          TcnEncoding encoding) {
  return formatAny(tcn, &info, comment, encoding);
}

void saveTcnFile(const Tcn& tcn, const TcnFileInfo& info, const std::string& path,
                 const std::string& comment, TcnEncoding encoding) {
  writeAtomically(path, formatTcnFile(tcn, info, comment, encoding));
}

std::string formatTcnWeights(const Tcn& tcn, const std::string& comment) {
  if (tcn.architecture().residual) return formatTcnFile(tcn, TcnFileInfo{}, comment);
  return formatAny(tcn, nullptr, comment, TcnEncoding::kText);
}

void saveTcnWeights(const Tcn& tcn, const std::string& path, const std::string& comment) {
  writeAtomically(path, formatTcnWeights(tcn, comment));
}

}  // namespace hdvio::learned
