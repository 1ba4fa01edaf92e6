// The contact times of one particle with a batch of candidates: the fast engine's inner loop.
//
// Each result is exactly contact_time(a, b, offset) (physics.hpp), `offset` being the image of b
// that a sees at `clock` (as Engine::image), bit for bit: the reference engine computes the same
// numbers pair by pair. A CPU with AVX2 computes four candidates at a time, with the same
// operations in the same order on each lane (no fused multiply-add: the library is built with
// -ffp-contract=off and the kernel's target does not include FMA), and without the branches on
// approach, contact and discriminant that a scalar loop mispredicts about every other candidate.
// Other CPUs take the scalar loop; tests/contact_batch_test.cpp checks that both agree.
#pragma once

#include <cstddef>
#include <cstdint>

#if defined(__x86_64__) && defined(__GNUC__)
#define CAROM_HAVE_AVX2_KERNEL 1
// GCC 12's AVX-512 intrinsics start from an "undefined" register it then calls uninitialized
// (GCC bug 105593, fixed in 13): silenced for the header's own lines only.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <immintrin.h>
#pragma GCC diagnostic pop
#endif

#include <algorithm>
#include <limits>
#include <type_traits>

#include "carom/core/physics.hpp"
#include "carom/core/system.hpp"

namespace carom {

// times[n] = contact_time(a, particles[candidates[n]], image offset at `clock`), for n < count
// (at most kMostContacts). `here` is position_at(a, clock); clock is not before any particle's
// stored time. A candidate that is `a` itself gets kNever (they are not approaching), so callers
// may pad a batch with it. Returns the set of n whose contact is finite and no later than
// `limit`, as bits: most candidates are receding or touch later than the best found so far, and
// the caller need not look at them.
inline constexpr std::size_t kMostContacts = 64;

// A particle read as doubles: position, velocity, time, radius, with nothing in between.
template <std::size_t D>
inline const double* raw(const Particle<D>& p) {
  static_assert(std::is_standard_layout_v<Particle<D>>);
  static_assert(offsetof(Particle<D>, velocity) == D * sizeof(double));
  static_assert(offsetof(Particle<D>, time) == 2 * D * sizeof(double));
  static_assert(offsetof(Particle<D>, radius) == (2 * D + 1) * sizeof(double));
  return reinterpret_cast<const double*>(&p);
}

// How a batch names its candidates: by index into the particles, or by offset, the index times
// the doubles a particle takes (kStride), which the CPU's addressing turns into the particle's
// address without an instruction of its own. Neighbour lists keep offsets; the cells, indices.
template <std::size_t D>
inline constexpr std::uint32_t kStride = sizeof(Particle<D>) / sizeof(double);

struct ByIndex {
  template <std::size_t D>
  static std::uint32_t index(std::uint32_t name) {
    return name;
  }
  template <std::size_t D>
  static const double* state(const Particle<D>* particles, std::uint32_t name) {
    return raw(particles[name]);
  }
};

struct ByOffset {
  template <std::size_t D>
  static std::uint32_t index(std::uint32_t name) {
    return name / kStride<D>;
  }
  template <std::size_t D>
  static const double* state(const Particle<D>* particles, std::uint32_t name) {
    return raw(particles[0]) + name;
  }
  // The offset of particle `index` (below 2^32 / kStride).
  template <std::size_t D>
  static std::uint32_t name(std::uint32_t index) {
    return index * kStride<D>;
  }
};

template <std::size_t D, class Names = ByIndex>
std::uint64_t contact_times_scalar(const Particle<D>& a, const Vec<D>& here, double clock,
                                   const Box<D>& box, const Particle<D>* particles,
                                   const std::uint32_t* candidates, std::size_t count, double limit,
                                   double* times, Names = {}) {
  std::uint64_t soon = 0;
  for (std::size_t n = 0; n < count; ++n) {
    const Particle<D>& b = particles[Names::template index<D>(candidates[n])];
    const Vec<D> offset =
        box.periodic() ? image_offset(here - position_at(b, clock), box) : Vec<D>{};
    times[n] = contact_time(a, b, offset);
    if (times[n] <= limit && times[n] != kNever) soon |= std::uint64_t{1} << n;
  }
  return soon;
}

// Which of `count` candidates (at most kMostContacts) have their point within `reach` of `centre`
// (through the nearest image in a periodic box), as bits: a neighbour list's test.
template <std::size_t D>
std::uint64_t near_points_scalar(const Vec<D>& centre, const Vec<D>* points,
                                 const std::uint32_t* candidates, std::size_t count,
                                 const Box<D>& box, double reach) {
  std::uint64_t near = 0;
  for (std::size_t n = 0; n < count; ++n) {
    Vec<D> apart = centre - points[candidates[n]];
    if (box.periodic()) apart -= image_offset(apart, box);
    if (norm2(apart) <= reach * reach) near |= std::uint64_t{1} << n;
  }
  return near;
}

// Four candidates at a time on a CPU with AVX2 (the tail of a batch that is not a multiple of four
// goes through the scalar loop).
template <std::size_t D>
std::uint64_t contact_times_avx2(const Particle<D>& a, const Vec<D>& here, double clock,
                                 const Box<D>& box, const Particle<D>* particles,
                                 const std::uint32_t* candidates, std::size_t count, double limit,
                                 double* times);

// Eight at a time on a CPU with AVX-512F (the tail through the scalar loop).
template <std::size_t D>
std::uint64_t contact_times_avx512(const Particle<D>& a, const Vec<D>& here, double clock,
                                   const Box<D>& box, const Particle<D>* particles,
                                   const std::uint32_t* candidates, std::size_t count, double limit,
                                   double* times);

// Whether this CPU runs contact_times_avx2 (otherwise it is the scalar loop).
bool cpu_has_avx2();
// Whether this CPU runs contact_times_avx512.
bool cpu_has_avx512();

// The contact kernels, narrowest first: what a prediction may be compiled for.
enum class ContactKernel : std::uint8_t { scalar, avx2, avx512 };
// The widest this CPU runs.
ContactKernel widest_contact_kernel();

#ifdef CAROM_HAVE_AVX2_KERNEL
// The four-wide loop itself, for callers compiled for AVX2 (a function with
// [[gnu::target("avx2")]]) to inline: `count` must be a multiple of four.
namespace contact_avx2 {

// Four candidates' states as lanes: coordinate k of the positions in x[k], and so on.
template <std::size_t D>
struct Lanes {
  __m256d x[D], v[D], time, radius;
};

// Rows [a b c d] of four particles become four columns (a0 a1 a2 a3), ... .
[[gnu::target("avx2")]] inline void transpose(__m256d& r0, __m256d& r1, __m256d& r2, __m256d& r3) {
  const __m256d t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);
  const __m256d t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);
  r0 = _mm256_permute2f128_pd(t0, t2, 0x20);
  r1 = _mm256_permute2f128_pd(t1, t3, 0x20);
  r2 = _mm256_permute2f128_pd(t0, t2, 0x31);
  r3 = _mm256_permute2f128_pd(t1, t3, 0x31);
}

template <class Names>
[[gnu::target("avx2")]] inline Lanes<3> load(const Particle<3>* particles, const std::uint32_t* c) {
  const double* p0 = Names::state(particles, c[0]);
  const double* p1 = Names::state(particles, c[1]);
  const double* p2 = Names::state(particles, c[2]);
  const double* p3 = Names::state(particles, c[3]);
  // [x y z vx] and [vy vz t radius]
  __m256d a0 = _mm256_loadu_pd(p0), a1 = _mm256_loadu_pd(p1), a2 = _mm256_loadu_pd(p2),
          a3 = _mm256_loadu_pd(p3);
  __m256d b0 = _mm256_loadu_pd(p0 + 4), b1 = _mm256_loadu_pd(p1 + 4), b2 = _mm256_loadu_pd(p2 + 4),
          b3 = _mm256_loadu_pd(p3 + 4);
  transpose(a0, a1, a2, a3);
  transpose(b0, b1, b2, b3);
  return {{a0, a1, a2}, {a3, b0, b1}, b2, b3};
}

template <class Names>
[[gnu::target("avx2")]] inline Lanes<2> load(const Particle<2>* particles, const std::uint32_t* c) {
  const double* p0 = Names::state(particles, c[0]);
  const double* p1 = Names::state(particles, c[1]);
  const double* p2 = Names::state(particles, c[2]);
  const double* p3 = Names::state(particles, c[3]);
  // [x y vx vy] and [t radius]
  __m256d a0 = _mm256_loadu_pd(p0), a1 = _mm256_loadu_pd(p1), a2 = _mm256_loadu_pd(p2),
          a3 = _mm256_loadu_pd(p3);
  transpose(a0, a1, a2, a3);
  const __m256d b02 = _mm256_set_m128d(_mm_loadu_pd(p2 + 4), _mm_loadu_pd(p0 + 4));
  const __m256d b13 = _mm256_set_m128d(_mm_loadu_pd(p3 + 4), _mm_loadu_pd(p1 + 4));
  return {{a0, a1}, {a2, a3}, _mm256_unpacklo_pd(b02, b13), _mm256_unpackhi_pd(b02, b13)};
}

// The sums of dot() and norm2() in their order. dot() starts from 0.0, which can only turn a -0
// into +0: no result depends on the sign of a zero relative velocity.
template <std::size_t D>
[[gnu::target("avx2")]] inline __m256d dot(const __m256d (&a)[D], const __m256d (&b)[D]) {
  __m256d s = _mm256_mul_pd(a[0], b[0]);
  for (std::size_t k = 1; k < D; ++k) s = _mm256_add_pd(s, _mm256_mul_pd(a[k], b[k]));
  return s;
}

// The loop of contact_times for one kind of box and of particle a (see there), so that neither
// is tested per batch and the compiler has the registers for the rest.
template <std::size_t D, bool periodic, bool a_now, class Names>
[[gnu::target("avx2")]] inline std::uint64_t contact_times_of(
    const Particle<D>& a, const Vec<D>& here, double clock, const Box<D>& box,
    const Particle<D>* particles, const std::uint32_t* candidates, std::size_t count, double limit,
    double* times) {
  const __m256d now = _mm256_set1_pd(clock), zero = _mm256_setzero_pd();
  const __m256d magnitude = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7FFFFFFFFFFFFFFF));
  const __m256d latest = _mm256_set1_pd(std::min(limit, std::numeric_limits<double>::max()));
  // a's state in registers before the loop: the stores to `times` might alias it otherwise.
  const __m256d a_radius = _mm256_set1_pd(a.radius), never = _mm256_set1_pd(kNever);
  const __m256d a_time = _mm256_set1_pd(a.time);
  __m256d at[D], a_x[D], a_v[D], half[D];
  for (std::size_t k = 0; k < D; ++k) {
    at[k] = _mm256_set1_pd(here[k]);
    a_x[k] = _mm256_set1_pd(a.position[k]);
    a_v[k] = _mm256_set1_pd(a.velocity[k]);
    half[k] = _mm256_set1_pd(0.5 * box.size[k]);
  }
  std::uint64_t soon = 0;
  for (std::size_t n = 0; n < count; n += 4) {
    const Lanes<D> b = load<Names>(particles, candidates + n);
    // The separation at the clock, for the image (image_offset), as position_at computes it.
    const __m256d since = _mm256_sub_pd(now, b.time);
    __m256d r[D], offset[D];
    for (std::size_t k = 0; k < D; ++k) {
      r[k] = _mm256_sub_pd(at[k], _mm256_add_pd(b.x[k], _mm256_mul_pd(b.v[k], since)));
    }
    bool shifted = false;
    if constexpr (periodic) {
      __m256d all = _mm256_cmp_pd(_mm256_and_pd(r[0], magnitude), half[0], _CMP_LE_OQ);
      for (std::size_t k = 1; k < D; ++k) {
        all =
            _mm256_and_pd(all, _mm256_cmp_pd(_mm256_and_pd(r[k], magnitude), half[k], _CMP_LE_OQ));
      }
      if (_mm256_movemask_pd(all) != 0xF) [[unlikely]] {  // some pair is seen across the box
        shifted = true;
        for (std::size_t k = 0; k < D; ++k) {
          const __m256d inside = _mm256_cmp_pd(_mm256_and_pd(r[k], magnitude), half[k], _CMP_LE_OQ);
          const __m256d side = _mm256_set1_pd(box.size[k]);
          const __m256d sides = _mm256_round_pd(_mm256_div_pd(r[k], side),
                                                _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
          offset[k] = _mm256_blendv_pd(_mm256_mul_pd(side, sides), zero, inside);
        }
      }
    }
    // The separation at the later of the two stored times, less the offset. After a collision
    // (most predictions) a is at the clock: that is the separation above.
    __m256d t0 = now;
    if constexpr (!a_now) {
      t0 = _mm256_max_pd(b.time, a_time);
      const __m256d a_dt = _mm256_sub_pd(t0, a_time), b_dt = _mm256_sub_pd(t0, b.time);
      for (std::size_t k = 0; k < D; ++k) {
        r[k] = _mm256_sub_pd(_mm256_add_pd(a_x[k], _mm256_mul_pd(a_v[k], a_dt)),
                             _mm256_add_pd(b.x[k], _mm256_mul_pd(b.v[k], b_dt)));
      }
    }
    if (shifted) {
      for (std::size_t k = 0; k < D; ++k) r[k] = _mm256_sub_pd(r[k], offset[k]);
    }
    __m256d v[D];
    for (std::size_t k = 0; k < D; ++k) v[k] = _mm256_sub_pd(a_v[k], b.v[k]);
    const __m256d rv = dot<D>(r, v);
    const __m256d approaching = _mm256_cmp_pd(rv, zero, _CMP_LT_OQ);
    const __m256d sigma = _mm256_add_pd(a_radius, b.radius);
    const __m256d c = _mm256_sub_pd(dot<D>(r, r), _mm256_mul_pd(sigma, sigma));
    const __m256d touching = _mm256_cmp_pd(c, zero, _CMP_LE_OQ);
    const __m256d discriminant =
        _mm256_sub_pd(_mm256_mul_pd(rv, rv), _mm256_mul_pd(dot<D>(v, v), c));
    // -rv + sqrt(discriminant), as sqrt(discriminant) - rv: the same sum.
    const __m256d root =
        _mm256_add_pd(t0, _mm256_div_pd(c, _mm256_sub_pd(_mm256_sqrt_pd(discriminant), rv)));
    const __m256d real = _mm256_cmp_pd(discriminant, zero, _CMP_NLT_UQ);
    __m256d t = _mm256_blendv_pd(never, root, real);
    t = _mm256_blendv_pd(t, t0, touching);
    t = _mm256_blendv_pd(never, t, approaching);
    _mm256_storeu_pd(times + n, t);
    // Finite and no later than the limit: no later than the limit or the largest double.
    const __m256d wanted = _mm256_cmp_pd(t, latest, _CMP_LE_OQ);
    soon |= static_cast<std::uint64_t>(_mm256_movemask_pd(wanted)) << n;
  }
  return soon;
}

template <std::size_t D, class Names = ByIndex>
[[gnu::target("avx2")]] inline std::uint64_t contact_times(const Particle<D>& a, const Vec<D>& here,
                                                           double clock, const Box<D>& box,
                                                           const Particle<D>* particles,
                                                           const std::uint32_t* candidates,
                                                           std::size_t count, double limit,
                                                           double* times, Names = {}) {
  // After a collision (most predictions) a's state is at the clock: the separation seen for the
  // image is the contact time's own (contact_time moves only the earlier particle, to a's time).
  const bool a_now = a.time == clock;
  if (box.periodic()) {
    return a_now ? contact_times_of<D, true, true, Names>(a, here, clock, box, particles,
                                                          candidates, count, limit, times)
                 : contact_times_of<D, true, false, Names>(a, here, clock, box, particles,
                                                           candidates, count, limit, times);
  }
  return a_now ? contact_times_of<D, false, true, Names>(a, here, clock, box, particles, candidates,
                                                         count, limit, times)
               : contact_times_of<D, false, false, Names>(a, here, clock, box, particles,
                                                          candidates, count, limit, times);
}

// near_points_scalar four at a time (`count` a multiple of four); `points` must be readable one
// double past its last point.
template <std::size_t D>
[[gnu::target("avx2")]] inline std::uint64_t near_points(const Vec<D>& centre, const Vec<D>* points,
                                                         const std::uint32_t* candidates,
                                                         std::size_t count, const Box<D>& box,
                                                         double reach) {
  static_assert(sizeof(Vec<D>) == D * sizeof(double));
  const __m256d magnitude = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7FFFFFFFFFFFFFFF));
  const __m256d reach2 = _mm256_set1_pd(reach * reach);
  const bool periodic = box.periodic();
  __m256d at[D], half[D];
  for (std::size_t k = 0; k < D; ++k) {
    at[k] = _mm256_set1_pd(centre[k]);
    half[k] = _mm256_set1_pd(0.5 * box.size[k]);
  }
  std::uint64_t near = 0;
  for (std::size_t n = 0; n < count; n += 4) {
    const double* p[4];
    for (std::size_t l = 0; l < 4; ++l) p[l] = points[candidates[n + l]].c.data();
    __m256d x[D];
    if constexpr (D == 3) {
      __m256d r0 = _mm256_loadu_pd(p[0]), r1 = _mm256_loadu_pd(p[1]), r2 = _mm256_loadu_pd(p[2]),
              r3 = _mm256_loadu_pd(p[3]);
      transpose(r0, r1, r2, r3);
      x[0] = r0, x[1] = r1, x[2] = r2;
    } else {
      const __m256d a02 = _mm256_set_m128d(_mm_loadu_pd(p[2]), _mm_loadu_pd(p[0]));
      const __m256d a13 = _mm256_set_m128d(_mm_loadu_pd(p[3]), _mm_loadu_pd(p[1]));
      x[0] = _mm256_unpacklo_pd(a02, a13), x[1] = _mm256_unpackhi_pd(a02, a13);
    }
    __m256d apart[D];
    for (std::size_t k = 0; k < D; ++k) apart[k] = _mm256_sub_pd(at[k], x[k]);
    if (periodic) {
      __m256d inside[D];
      for (std::size_t k = 0; k < D; ++k) {
        inside[k] = _mm256_cmp_pd(_mm256_and_pd(apart[k], magnitude), half[k], _CMP_LE_OQ);
      }
      __m256d all = inside[0];
      for (std::size_t k = 1; k < D; ++k) all = _mm256_and_pd(all, inside[k]);
      if (_mm256_movemask_pd(all) != 0xF) [[unlikely]] {
        for (std::size_t k = 0; k < D; ++k) {
          const __m256d side = _mm256_set1_pd(box.size[k]);
          const __m256d sides = _mm256_round_pd(_mm256_div_pd(apart[k], side),
                                                _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
          apart[k] = _mm256_sub_pd(apart[k], _mm256_blendv_pd(_mm256_mul_pd(side, sides),
                                                              _mm256_setzero_pd(), inside[k]));
        }
      }
    }
    const __m256d within = _mm256_cmp_pd(dot<D>(apart, apart), reach2, _CMP_LE_OQ);
    near |= static_cast<std::uint64_t>(_mm256_movemask_pd(within)) << n;
  }
  return near;
}

}  // namespace contact_avx2

// The same eight candidates at a time, for callers compiled for AVX-512F: `count` must be a
// multiple of eight. The lanes are gathered from the particles field by field (one instruction
// each, where a transposition takes three a field), and the comparisons give bit masks directly.
// Each lane computes what contact_avx2 computes, operation for operation.
namespace contact_avx512 {

template <std::size_t D>
struct Lanes {
  __m512d x[D], v[D], time, radius;
};

// The offsets, in doubles, of eight array elements `stride` doubles long.
template <std::size_t stride>
[[gnu::target("avx512f")]] inline __m512i element_offsets(const std::uint32_t* c) {
  static_assert(stride == 2 || stride == 3);
  const __m512i i = _mm512_cvtepu32_epi64(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(c)));
  if constexpr (stride == 2) return _mm512_slli_epi64(i, 1);
  return _mm512_add_epi64(_mm512_slli_epi64(i, 1), i);
}

// Eight particles' states (at most eight doubles each) as lanes: row l is particle l's doubles,
// column k of the result field k of the eight. Three rounds of eight shuffles, each within
// pairs of rows, then of 128-bit blocks, then of 256-bit halves.
template <class Names, std::size_t D>
[[gnu::target("avx512f")]] inline Lanes<D> load(const Particle<D>* particles,
                                                const std::uint32_t* c) {
  constexpr std::size_t fields = 2 * D + 2;  // position, velocity, time, radius
  static_assert(sizeof(Particle<D>) == fields * sizeof(double) && fields <= 8);
  constexpr __mmask8 whole = static_cast<__mmask8>((1u << fields) - 1);
  __m512d row[8];
  for (std::size_t l = 0; l < 8; ++l) {
    row[l] = _mm512_maskz_loadu_pd(whole, Names::state(particles, c[l]));
  }
  __m512d pair[8], block[8], field[8];
  for (std::size_t l = 0; l < 8; l += 2) {
    pair[l] = _mm512_unpacklo_pd(row[l], row[l + 1]);      // fields 0 2 4 6 of rows l, l + 1
    pair[l + 1] = _mm512_unpackhi_pd(row[l], row[l + 1]);  // fields 1 3 5 7
  }
  for (std::size_t h = 0; h < 2; ++h) {
    for (std::size_t odd = 0; odd < 2; ++odd) {
      const __m512d a = pair[4 * h + odd], b = pair[4 * h + 2 + odd];
      block[4 * h + odd] = _mm512_shuffle_f64x2(a, b, 0x88);      // fields 0 4 (or 1 5)
      block[4 * h + 2 + odd] = _mm512_shuffle_f64x2(a, b, 0xDD);  // fields 2 6 (or 3 7)
    }
  }
  for (std::size_t q = 0; q < 4; ++q) {
    // block[q] holds fields f and f + 4 of rows 0-3, block[q + 4] of rows 4-7.
    const std::size_t f = q % 2 + 2 * (q / 2);
    field[f] = _mm512_shuffle_f64x2(block[q], block[q + 4], 0x88);
    field[f + 4] = _mm512_shuffle_f64x2(block[q], block[q + 4], 0xDD);
  }
  Lanes<D> lanes;
  for (std::size_t k = 0; k < D; ++k) {
    lanes.x[k] = field[k];
    lanes.v[k] = field[D + k];
  }
  lanes.time = field[2 * D];
  lanes.radius = field[2 * D + 1];
  return lanes;
}

template <std::size_t D>
[[gnu::target("avx512f")]] inline __m512d dot(const __m512d (&a)[D], const __m512d (&b)[D]) {
  __m512d s = _mm512_mul_pd(a[0], b[0]);
  for (std::size_t k = 1; k < D; ++k) s = _mm512_add_pd(s, _mm512_mul_pd(a[k], b[k]));
  return s;
}

template <std::size_t D, bool periodic, bool a_now, class Names>
[[gnu::target("avx512f")]] inline std::uint64_t contact_times_of(
    const Particle<D>& a, const Vec<D>& here, double clock, const Box<D>& box,
    const Particle<D>* particles, const std::uint32_t* candidates, std::size_t count, double limit,
    double* times) {
  const __m512d now = _mm512_set1_pd(clock), zero = _mm512_setzero_pd();
  const __m512d latest = _mm512_set1_pd(std::min(limit, std::numeric_limits<double>::max()));
  const __m512d a_radius = _mm512_set1_pd(a.radius), never = _mm512_set1_pd(kNever);
  const __m512d a_time = _mm512_set1_pd(a.time);
  __m512d at[D], a_x[D], a_v[D], half[D];
  for (std::size_t k = 0; k < D; ++k) {
    at[k] = _mm512_set1_pd(here[k]);
    a_x[k] = _mm512_set1_pd(a.position[k]);
    a_v[k] = _mm512_set1_pd(a.velocity[k]);
    half[k] = _mm512_set1_pd(0.5 * box.size[k]);
  }
  std::uint64_t soon = 0;
  for (std::size_t n = 0; n < count; n += 8) {
    const Lanes<D> b = load<Names>(particles, candidates + n);
    const __m512d since = _mm512_sub_pd(now, b.time);
    __m512d r[D], offset[D];
    for (std::size_t k = 0; k < D; ++k) {
      r[k] = _mm512_sub_pd(at[k], _mm512_add_pd(b.x[k], _mm512_mul_pd(b.v[k], since)));
    }
    bool shifted = false;
    if constexpr (periodic) {
      __mmask8 inside[D];
      __mmask8 all = 0xFF;
      for (std::size_t k = 0; k < D; ++k) {
        inside[k] = _mm512_cmp_pd_mask(_mm512_abs_pd(r[k]), half[k], _CMP_LE_OQ);
        all &= inside[k];
      }
      if (all != 0xFF) [[unlikely]] {  // some pair is seen across the box
        shifted = true;
        for (std::size_t k = 0; k < D; ++k) {
          const __m512d side = _mm512_set1_pd(box.size[k]);
          const __m512d sides = _mm512_roundscale_pd(_mm512_div_pd(r[k], side),
                                                     _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
          offset[k] =
              _mm512_maskz_mov_pd(static_cast<__mmask8>(~inside[k]), _mm512_mul_pd(side, sides));
        }
      }
    }
    __m512d t0 = now;
    if constexpr (!a_now) {
      t0 = _mm512_max_pd(b.time, a_time);
      const __m512d a_dt = _mm512_sub_pd(t0, a_time), b_dt = _mm512_sub_pd(t0, b.time);
      for (std::size_t k = 0; k < D; ++k) {
        r[k] = _mm512_sub_pd(_mm512_add_pd(a_x[k], _mm512_mul_pd(a_v[k], a_dt)),
                             _mm512_add_pd(b.x[k], _mm512_mul_pd(b.v[k], b_dt)));
      }
    }
    if (shifted) {
      for (std::size_t k = 0; k < D; ++k) r[k] = _mm512_sub_pd(r[k], offset[k]);
    }
    __m512d v[D];
    for (std::size_t k = 0; k < D; ++k) v[k] = _mm512_sub_pd(a_v[k], b.v[k]);
    const __m512d rv = dot<D>(r, v);
    const __mmask8 approaching = _mm512_cmp_pd_mask(rv, zero, _CMP_LT_OQ);
    const __m512d sigma = _mm512_add_pd(a_radius, b.radius);
    const __m512d c = _mm512_sub_pd(dot<D>(r, r), _mm512_mul_pd(sigma, sigma));
    const __mmask8 touching = _mm512_cmp_pd_mask(c, zero, _CMP_LE_OQ);
    const __m512d discriminant =
        _mm512_sub_pd(_mm512_mul_pd(rv, rv), _mm512_mul_pd(dot<D>(v, v), c));
    const __m512d root =
        _mm512_add_pd(t0, _mm512_div_pd(c, _mm512_sub_pd(_mm512_sqrt_pd(discriminant), rv)));
    const __mmask8 real = _mm512_cmp_pd_mask(discriminant, zero, _CMP_NLT_UQ);
    __m512d t = _mm512_mask_blend_pd(real, never, root);
    t = _mm512_mask_blend_pd(touching, t, t0);
    t = _mm512_mask_blend_pd(approaching, never, t);
    _mm512_storeu_pd(times + n, t);
    const __mmask8 wanted = _mm512_cmp_pd_mask(t, latest, _CMP_LE_OQ);
    soon |= static_cast<std::uint64_t>(wanted) << n;
  }
  return soon;
}

template <std::size_t D, class Names = ByIndex>
[[gnu::target("avx512f")]] inline std::uint64_t contact_times(
    const Particle<D>& a, const Vec<D>& here, double clock, const Box<D>& box,
    const Particle<D>* particles, const std::uint32_t* candidates, std::size_t count, double limit,
    double* times, Names = {}) {
  const bool a_now = a.time == clock;  // see contact_avx2::contact_times
  if (box.periodic()) {
    return a_now ? contact_times_of<D, true, true, Names>(a, here, clock, box, particles,
                                                          candidates, count, limit, times)
                 : contact_times_of<D, true, false, Names>(a, here, clock, box, particles,
                                                           candidates, count, limit, times);
  }
  return a_now ? contact_times_of<D, false, true, Names>(a, here, clock, box, particles, candidates,
                                                         count, limit, times)
               : contact_times_of<D, false, false, Names>(a, here, clock, box, particles,
                                                          candidates, count, limit, times);
}

// contact_avx2::near_points eight at a time (`count` a multiple of eight).
template <std::size_t D>
[[gnu::target("avx512f")]] inline std::uint64_t near_points(const Vec<D>& centre,
                                                            const Vec<D>* points,
                                                            const std::uint32_t* candidates,
                                                            std::size_t count, const Box<D>& box,
                                                            double reach) {
  static_assert(sizeof(Vec<D>) == D * sizeof(double));
  const __m512d reach2 = _mm512_set1_pd(reach * reach);
  const bool periodic = box.periodic();
  const double* base = points[0].c.data();
  __m512d at[D], half[D], side[D];
  for (std::size_t k = 0; k < D; ++k) {
    at[k] = _mm512_set1_pd(centre[k]);
    half[k] = _mm512_set1_pd(0.5 * box.size[k]);
    side[k] = _mm512_set1_pd(box.size[k]);
  }
  std::uint64_t near = 0;
  for (std::size_t n = 0; n < count; n += 8) {
    const __m512i offsets = element_offsets<D>(candidates + n);
    __m512d apart[D];
    for (std::size_t k = 0; k < D; ++k) {
      apart[k] = _mm512_sub_pd(at[k], _mm512_i64gather_pd(offsets, base + k, 8));
    }
    if (periodic) {
      __mmask8 inside[D];
      __mmask8 all = 0xFF;
      for (std::size_t k = 0; k < D; ++k) {
        inside[k] = _mm512_cmp_pd_mask(_mm512_abs_pd(apart[k]), half[k], _CMP_LE_OQ);
        all &= inside[k];
      }
      if (all != 0xFF) [[unlikely]] {
        for (std::size_t k = 0; k < D; ++k) {
          const __m512d sides = _mm512_roundscale_pd(_mm512_div_pd(apart[k], side[k]),
                                                     _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
          apart[k] = _mm512_sub_pd(apart[k], _mm512_maskz_mov_pd(static_cast<__mmask8>(~inside[k]),
                                                                 _mm512_mul_pd(side[k], sides)));
        }
      }
    }
    const __mmask8 within = _mm512_cmp_pd_mask(dot<D>(apart, apart), reach2, _CMP_LE_OQ);
    near |= static_cast<std::uint64_t>(within) << n;
  }
  return near;
}

}  // namespace contact_avx512
#endif

}  // namespace carom
