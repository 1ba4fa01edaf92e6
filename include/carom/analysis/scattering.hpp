// Scattering from a trajectory's frames, what glass and relaxation studies read: the static
// structure factor S(k) on the periodic box's k-grid, and the self-intermediate scattering
// function F_s(k,t) with the non-Gaussian parameter alpha2(t) and the alpha relaxation time.
// Pure functions of the frames: nothing here reads files or prints.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include "carom/io/trajectory_reader.hpp"

namespace carom {

// The box's k-grid, k = 2 pi (n_x / L_x, n_y / L_y[, n_z / L_z]) for whole n, in shells of |k| of
// width dk = 2 pi / L_min (L_min the smallest side): shell m >= 1 holds the k with |k| in
// [(m - 1/2) dk, (m + 1/2) dk). Only one of k and -k is kept (the first nonzero n positive):
// S(k) and cos(k . r) are the same at both. So that the cost stays bounded (S(k) costs N a
// k-vector and frame), a shell of more than kWaveVectorsPerShell vectors keeps that many, chosen
// without randomness: with the shell's vectors in lexicographic order of (n_x, n_y, n_z) and
// counted from 0, those at floor(j count / kWaveVectorsPerShell), j = 0, 1, ... Shell m holds
// about pi m vectors in 2D, 2 pi m^2 in 3D: beyond m = 31 in 2D and m = 3 in 3D, the cap applies.
constexpr std::size_t kWaveVectorsPerShell = 100;

struct WaveShell {
  double k = 0.0;                         // the mean |k| of the vectors kept
  std::vector<std::array<int, 3>> index;  // their n (n_z = 0 in 2D)
};

// Shells 1 to `shells` of the k-grid of a box of `dimension` sides. Throws std::invalid_argument
// when the grid up to there holds more than 10^8 points (a k far beyond any structure).
std::vector<WaveShell> wave_shells(int dimension, const Vec<3>& box, std::size_t shells);

// The shell width dk = 2 pi / L_min of a frame's box.
double wave_number_step(const Frame& frame);

// S(k) = |sum_j exp(-i k . r_j)|^2 / N of one frame at each k-vector n of its box's grid (the
// positions as they are: S is the same at every periodic image).
std::vector<double> structure_factor_at(const Frame& frame,
                                        const std::vector<std::array<int, 3>>& index);

// S(k) is a static average, and a frame's shells already average many k-vectors: a long
// trajectory's S(k) is taken on at most this many of its frames, evenly spread (frame
// floor(j F / kStructureFactorFrames) of F, j = 0, 1, ...), at a small fraction of the cost of all.
constexpr std::size_t kStructureFactorFrames = 20;
// S(k) averaged over the frames (see kStructureFactorFrames) and the k-vectors of each shell,
// shells 1 up to k_max
// (every shell whose centre m dk is at most k_max), at each shell's mean |k|; k_peak is the k of
// its highest shell (the main peak of a fluid or a glass). For a periodic box; throws
// std::invalid_argument for a box that is not, or a k_max below dk.
struct StructureFactor {
  std::vector<double> k, s;
  double k_peak = 0.0;
};
StructureFactor structure_factor(const std::vector<Frame>& frames, double k_max);

// At the lags of the MSD (displacement_lags), averaged over every particle and time origin:
// F_s(k,t) = <(1/N) sum_j cos(k . (r_j(t0 + t) - r_j(t0)))> over the k-vectors of the grid's shell
// that holds |k| = `k` (k the shell's mean |k|), of the unwrapped positions; alpha2(t) = D <dr^4>
// / ((D + 2) <dr^2>^2) - 1, NaN at t = 0 (and wherever no particle moved); tau_alpha, the first
// time F_s falls below 1/e, linearly interpolated between the lags on either side (nullopt if it
// never does). Throws std::invalid_argument as unwrap() does (frames not evenly spaced, a periodic
// trajectory without image flags) and for a k below dk / 2 (the shell of k = 0).
struct SelfScattering {
  double k = 0.0;
  std::vector<double> t, fs, alpha2;
  std::optional<double> tau_alpha;
};
SelfScattering self_scattering(const std::vector<Frame>& frames, double k,
                               bool from_centre_of_mass = false);

// The first time f falls below 1/e, linearly interpolated between the samples on either side.
std::optional<double> relaxation_time(const std::vector<double>& t, const std::vector<double>& f);

}  // namespace carom
