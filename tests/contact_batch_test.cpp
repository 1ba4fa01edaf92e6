// The contact kernels (src/engine/contact_batch.hpp): the four- and eight-wide ones give the scalar
// one's times bit for bit, and the scalar one is contact_time with the image seen at the clock, as
// the reference engine computes it; the same for the wide distance tests that make neighbour lists.
#include "engine/contact_batch.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "carom/core/physics.hpp"

namespace carom {
namespace {

// Random particles around the box, many of them touching, overlapping by round-off, seen across
// a periodic edge, stored at the clock or earlier, at equal times, or still.
template <std::size_t D>
struct RandomBatch {
  Box<D> box;
  std::vector<Particle<D>> particles;
  std::vector<std::uint32_t> candidates;
  double clock = 0.0;
};

template <std::size_t D>
RandomBatch<D> random_batch(std::mt19937_64& rng, bool periodic, std::size_t count) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  RandomBatch<D> batch;
  for (std::size_t k = 0; k < D; ++k) batch.box.size[k] = 6.0 + 10.0 * unit(rng);
  batch.box.boundary = periodic ? Boundary::periodic : Boundary::walls;
  batch.clock = unit(rng) < 0.2 ? 0.0 : 10.0 * unit(rng);
  const auto random_particle = [&] {
    Particle<D> p;
    for (std::size_t k = 0; k < D; ++k) {
      // Some outside the box: a periodic position is wrapped only at collisions.
      p.position[k] = batch.box.size[k] * (1.4 * unit(rng) - 0.2);
      p.velocity[k] = unit(rng) < 0.1 ? 0.0 : 4.0 * unit(rng) - 2.0;
    }
    p.radius = unit(rng) < 0.5 ? 0.5 : 0.1 + unit(rng);
    const double pick = unit(rng);
    p.time = pick < 0.3 ? batch.clock : pick < 0.4 ? 0.0 : batch.clock * unit(rng);
    return p;
  };
  const Particle<D> a = random_particle();
  batch.particles.push_back(a);
  for (std::size_t n = 0; n < count; ++n) {
    Particle<D> b = random_particle();
    if (unit(rng) < 0.4) {
      // Near contact with a at the later of their times, one way or another across the box.
      const double t0 = std::max(a.time, b.time);
      Vec<D> direction;
      for (std::size_t k = 0; k < D; ++k) direction[k] = unit(rng) - 0.5;
      direction *= 1.0 / std::sqrt(norm2(direction));
      const double gap = unit(rng) < 0.3 ? 0.0 : 1e-12 * (unit(rng) - 0.5) + unit(rng) * 0.3;
      Vec<D> at = position_at(a, t0) + direction * (a.radius + b.radius + gap);
      if (periodic && unit(rng) < 0.5) at[0] += batch.box.size[0] * (unit(rng) < 0.5 ? 1 : -1);
      b.position = at - b.velocity * (t0 - b.time);
    }
    batch.particles.push_back(b);
  }
  for (std::uint32_t n = 0; n < count; ++n) batch.candidates.push_back(n + 1);
  batch.candidates.push_back(0);  // a itself: never
  return batch;
}

template <std::size_t D>
void check_kernels_agree(bool periodic) {
  std::mt19937_64 rng(periodic ? 7 : 11);
  for (int trial = 0; trial < 20000; ++trial) {
    const RandomBatch<D> batch = random_batch<D>(rng, periodic, 1 + trial % 63);
    const Particle<D>& a = batch.particles[0];
    const Vec<D> here = position_at(a, batch.clock);
    const std::size_t count = batch.candidates.size();
    const double limit = trial % 3 == 0 ? kNever : batch.clock + 0.5;
    std::vector<double> scalar(count), wide(count);
    const std::uint64_t scalar_soon =
        contact_times_scalar(a, here, batch.clock, batch.box, batch.particles.data(),
                             batch.candidates.data(), count, limit, scalar.data());
    for (std::size_t n = 0; n < count; ++n) {
      const Particle<D>& b = batch.particles[batch.candidates[n]];
      const Vec<D> offset =
          periodic ? image_offset(here - position_at(b, batch.clock), batch.box) : Vec<D>{};
      ASSERT_EQ(std::bit_cast<std::uint64_t>(scalar[n]),
                std::bit_cast<std::uint64_t>(contact_time(a, b, offset)));
      const bool soon = scalar[n] <= limit && scalar[n] != kNever;
      ASSERT_EQ(((scalar_soon >> n) & 1) != 0, soon) << "candidate " << n;
    }
    ASSERT_EQ(scalar.back(), kNever) << "a particle is no contact of its own";
    if (cpu_has_avx2()) {
      const std::uint64_t wide_soon =
          contact_times_avx2(a, here, batch.clock, batch.box, batch.particles.data(),
                             batch.candidates.data(), count, limit, wide.data());
      ASSERT_EQ(wide_soon, scalar_soon) << "trial " << trial;
      ASSERT_EQ(std::memcmp(wide.data(), scalar.data(), count * sizeof(double)), 0)
          << "trial " << trial;
    }
    if (cpu_has_avx512()) {
      std::fill(wide.begin(), wide.end(), 0.0);
      const std::uint64_t wider_soon =
          contact_times_avx512(a, here, batch.clock, batch.box, batch.particles.data(),
                               batch.candidates.data(), count, limit, wide.data());
      ASSERT_EQ(wider_soon, scalar_soon) << "trial " << trial;
      ASSERT_EQ(std::memcmp(wide.data(), scalar.data(), count * sizeof(double)), 0)
          << "trial " << trial;
    }
  }
  if (!cpu_has_avx2()) GTEST_SKIP() << "this CPU has no AVX2: only the scalar kernel checked";
  if (!cpu_has_avx512())
    GTEST_SKIP() << "this CPU has no AVX-512F: the eight-wide kernel unchecked";
}

#ifdef CAROM_HAVE_AVX2_KERNEL
template <std::size_t D>
[[gnu::target("avx2")]] std::uint64_t near_points_avx2(const Vec<D>& centre,
                                                       const std::vector<Vec<D>>& points,
                                                       const std::uint32_t* candidates,
                                                       std::size_t count, const Box<D>& box,
                                                       double reach) {
  return contact_avx2::near_points(centre, points.data(), candidates, count, box, reach);
}

template <std::size_t D>
[[gnu::target("avx512f")]] std::uint64_t near_points_avx512(const Vec<D>& centre,
                                                            const std::vector<Vec<D>>& points,
                                                            const std::uint32_t* candidates,
                                                            std::size_t count, const Box<D>& box,
                                                            double reach) {
  return contact_avx512::near_points(centre, points.data(), candidates, count, box, reach);
}

// Points within reach or just beyond it, some across a periodic edge: the wide tests find the
// scalar one's, bit for bit.
template <std::size_t D>
void check_near_points_agree(bool periodic) {
  std::mt19937_64 rng(periodic ? 17 : 19);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 5000; ++trial) {
    Box<D> box;
    for (std::size_t k = 0; k < D; ++k) box.size[k] = 6.0 + 10.0 * unit(rng);
    box.boundary = periodic ? Boundary::periodic : Boundary::walls;
    const double reach = 0.5 + 2.0 * unit(rng);
    const std::size_t count = 8 * (1 + trial % 8);
    std::vector<Vec<D>> points(count + 2);  // one more than read, as for the engine's centres
    Vec<D> centre;
    for (std::size_t k = 0; k < D; ++k) centre[k] = box.size[k] * unit(rng);
    std::vector<std::uint32_t> candidates(count);
    for (std::uint32_t n = 0; n < count; ++n) {
      Vec<D> direction;
      for (std::size_t k = 0; k < D; ++k) direction[k] = unit(rng) - 0.5;
      direction *= 1.0 / std::sqrt(norm2(direction));
      const double distance = unit(rng) < 0.3 ? reach : reach * 2.0 * unit(rng);
      points[n + 1] = centre + direction * distance;
      if (periodic && unit(rng) < 0.5) points[n + 1][0] += box.size[0] * (unit(rng) < 0.5 ? 1 : -1);
      candidates[n] = n + 1;
    }
    const std::uint64_t scalar =
        near_points_scalar(centre, points.data(), candidates.data(), count, box, reach);
    if (cpu_has_avx2()) {
      ASSERT_EQ(near_points_avx2(centre, points, candidates.data(), count, box, reach), scalar)
          << "trial " << trial;
    }
    if (cpu_has_avx512()) {
      ASSERT_EQ(near_points_avx512(centre, points, candidates.data(), count, box, reach), scalar)
          << "trial " << trial;
    }
  }
  if (!cpu_has_avx512()) GTEST_SKIP() << "this CPU has no AVX-512F: the eight-wide test unchecked";
}

TEST(NearPoints, TheWideTestsAreTheScalarOneForDisks) {
  check_near_points_agree<2>(false);
  check_near_points_agree<2>(true);
}
TEST(NearPoints, TheWideTestsAreTheScalarOneForSpheres) {
  check_near_points_agree<3>(false);
  check_near_points_agree<3>(true);
}
#endif

TEST(ContactBatch, TheWideKernelIsTheScalarOneBitForBitForDisksBetweenWalls) {
  check_kernels_agree<2>(false);
}
TEST(ContactBatch, TheWideKernelIsTheScalarOneBitForBitForPeriodicDisks) {
  check_kernels_agree<2>(true);
}
TEST(ContactBatch, TheWideKernelIsTheScalarOneBitForBitForSpheresBetweenWalls) {
  check_kernels_agree<3>(false);
}
TEST(ContactBatch, TheWideKernelIsTheScalarOneBitForBitForPeriodicSpheres) {
  check_kernels_agree<3>(true);
}

}  // namespace
}  // namespace carom
