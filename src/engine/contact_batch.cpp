#include "contact_batch.hpp"

namespace carom {

#ifdef CAROM_HAVE_AVX2_KERNEL

template <std::size_t D>
[[gnu::target("avx2")]] std::uint64_t contact_times_avx2(const Particle<D>& a, const Vec<D>& here,
                                                         double clock, const Box<D>& box,
                                                         const Particle<D>* particles,
                                                         const std::uint32_t* candidates,
                                                         std::size_t count, double limit,
                                                         double* times) {
  const std::size_t whole = count - count % 4;
  std::uint64_t soon = contact_avx2::contact_times<D>(a, here, clock, box, particles, candidates,
                                                      whole, limit, times);
  if (whole < count) {
    soon |= contact_times_scalar(a, here, clock, box, particles, candidates + whole, count - whole,
                                 limit, times + whole)
            << whole;
  }
  return soon;
}

template <std::size_t D>
[[gnu::target("avx512f")]] std::uint64_t contact_times_avx512(
    const Particle<D>& a, const Vec<D>& here, double clock, const Box<D>& box,
    const Particle<D>* particles, const std::uint32_t* candidates, std::size_t count, double limit,
    double* times) {
  const std::size_t whole = count - count % 8;
  std::uint64_t soon = contact_avx512::contact_times<D>(a, here, clock, box, particles, candidates,
                                                        whole, limit, times);
  if (whole < count) {
    soon |= contact_times_scalar(a, here, clock, box, particles, candidates + whole, count - whole,
                                 limit, times + whole)
            << whole;
  }
  return soon;
}

bool cpu_has_avx2() {
  return __builtin_cpu_supports("avx2");
}
bool cpu_has_avx512() {
  return __builtin_cpu_supports("avx512f");
}

#else

template <std::size_t D>
std::uint64_t contact_times_avx2(const Particle<D>& a, const Vec<D>& here, double clock,
                                 const Box<D>& box, const Particle<D>* particles,
                                 const std::uint32_t* candidates, std::size_t count, double limit,
                                 double* times) {
  return contact_times_scalar(a, here, clock, box, particles, candidates, count, limit, times);
}

template <std::size_t D>
std::uint64_t contact_times_avx512(const Particle<D>& a, const Vec<D>& here, double clock,
                                   const Box<D>& box, const Particle<D>* particles,
                                   const std::uint32_t* candidates, std::size_t count, double limit,
                                   double* times) {
  return contact_times_scalar(a, here, clock, box, particles, candidates, count, limit, times);
}

bool cpu_has_avx2() {
  return false;
}
bool cpu_has_avx512() {
  return false;
}

#endif

ContactKernel widest_contact_kernel() {
  if (cpu_has_avx512()) return ContactKernel::avx512;
  return cpu_has_avx2() ? ContactKernel::avx2 : ContactKernel::scalar;
}

template std::uint64_t contact_times_avx2(const Particle<2>&, const Vec<2>&, double, const Box<2>&,
                                          const Particle<2>*, const std::uint32_t*, std::size_t,
                                          double, double*);
template std::uint64_t contact_times_avx2(const Particle<3>&, const Vec<3>&, double, const Box<3>&,
                                          const Particle<3>*, const std::uint32_t*, std::size_t,
                                          double, double*);

template std::uint64_t contact_times_avx512(const Particle<2>&, const Vec<2>&, double,
                                            const Box<2>&, const Particle<2>*, const std::uint32_t*,
                                            std::size_t, double, double*);
template std::uint64_t contact_times_avx512(const Particle<3>&, const Vec<3>&, double,
                                            const Box<3>&, const Particle<3>*, const std::uint32_t*,
                                            std::size_t, double, double*);

}  // namespace carom
