#pragma once
// Typed 64-bit symbols for variables, GTSAM style: the top byte is a letter, the rest an index.
// X(k) pose, V(k) velocity, B(k) IMU biases [bg, ba], F(k) external force, L(j) landmark.
#include <cstdint>
#include <functional>
#include <ostream>
#include <string>

namespace hdvio {

class Key {
 public:
  constexpr Key() = default;
  constexpr Key(char letter, std::uint64_t index)
      : value_((static_cast<std::uint64_t>(static_cast<unsigned char>(letter)) << 56) |
               (index & kIndexMask)) {}

  constexpr char letter() const { return static_cast<char>(value_ >> 56); }
  constexpr std::uint64_t index() const { return value_ & kIndexMask; }
  constexpr std::uint64_t value() const { return value_; }
  std::string str() const { return std::string(1, letter()) + std::to_string(index()); }

  friend constexpr bool operator==(Key a, Key b) { return a.value_ == b.value_; }
  friend constexpr bool operator!=(Key a, Key b) { return a.value_ != b.value_; }
  friend constexpr bool operator<(Key a, Key b) { return a.value_ < b.value_; }
  friend std::ostream& operator<<(std::ostream& os, Key k) { return os << k.str(); }

 private:
  static constexpr std::uint64_t kIndexMask = (std::uint64_t{1} << 56) - 1;
  std::uint64_t value_ = 0;
};

namespace symbols {
constexpr Key X(std::uint64_t k) { return Key('x', k); }  // pose T_WB
constexpr Key V(std::uint64_t k) { return Key('v', k); }  // velocity v_W
constexpr Key B(std::uint64_t k) { return Key('b', k); }  // biases [bg, ba]
constexpr Key F(std::uint64_t k) { return Key('f', k); }  // external force (mass-normalized, W)
constexpr Key L(std::uint64_t j) { return Key('l', j); }  // landmark
}  // namespace symbols

}  // namespace hdvio

template <> struct std::hash<hdvio::Key> {
  std::size_t operator()(hdvio::Key k) const noexcept { return std::hash<std::uint64_t>()(k.value()); }
};
