// A small fixed-dimension vector: the only geometry type the engine uses, so that the same
// physics and event code serves hard disks (D = 2) and hard spheres (D = 3).
#pragma once

#include <array>
#include <cstddef>

namespace carom {

template <std::size_t D>
struct Vec {
  std::array<double, D> c{};

  constexpr double& operator[](std::size_t k) { return c[k]; }
  constexpr double operator[](std::size_t k) const { return c[k]; }

  constexpr Vec& operator+=(const Vec& o) {
    for (std::size_t k = 0; k < D; ++k) c[k] += o.c[k];
    return *this;
  }
  constexpr Vec& operator-=(const Vec& o) {
    for (std::size_t k = 0; k < D; ++k) c[k] -= o.c[k];
    return *this;
  }
  constexpr Vec& operator*=(double s) {
    for (std::size_t k = 0; k < D; ++k) c[k] *= s;
    return *this;
  }
  friend constexpr Vec operator+(Vec a, const Vec& b) { return a += b; }
  friend constexpr Vec operator-(Vec a, const Vec& b) { return a -= b; }
  friend constexpr Vec operator*(Vec a, double s) { return a *= s; }
  friend constexpr Vec operator*(double s, Vec a) { return a *= s; }
  friend constexpr Vec operator-(Vec a) { return a *= -1.0; }
  friend constexpr bool operator==(const Vec&, const Vec&) = default;
};

template <std::size_t D>
constexpr double dot(const Vec<D>& a, const Vec<D>& b) {
  double s = 0.0;
  for (std::size_t k = 0; k < D; ++k) s += a[k] * b[k];
  return s;
}

// The same as dot(a, a), bit for bit (squares are never -0, so the sum needs no 0.0 to start).
template <std::size_t D>
constexpr double norm2(const Vec<D>& a) {
  double s = a[0] * a[0];
  for (std::size_t k = 1; k < D; ++k) s += a[k] * a[k];
  return s;
}

using Vec2 = Vec<2>;

}  // namespace carom
