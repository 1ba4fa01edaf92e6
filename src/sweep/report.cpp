// A sweep's report: each measure's state-point means with their standard errors against the first
// numeric axis, drawn as SVG here (no script, no network: the page is the same bytes for the same
// results), and Z beside the equation of state of hard disks or spheres where one applies.
#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <unordered_map>

#include "carom/core/equation_of_state.hpp"
#include "carom/run/z_drift.hpp"
#include "carom/sweep/sweep.hpp"
#include "state_points.hpp"

namespace carom {

namespace {

using sweep::Estimate;
using sweep::StatePoints;

std::string escaped(std::string_view text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::optional<double> number(const std::string& text) {
  double x = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), x);
  if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(x)) {
    return std::nullopt;
  }
  return x;
}

// The first axis whose every value is a number: what the charts have along x.
std::optional<std::size_t> x_axis(const StatePoints& s) {
  for (std::size_t a = 0; a < s.axes.size(); ++a) {
    if (std::all_of(s.points.begin(), s.points.end(),
                    [&](const auto& p) { return number(p.values[a]).has_value(); })) {
      return a;
    }
  }
  return std::nullopt;
}

// The reference equation of state for Z against phi: runs of equal disks or spheres, of one
// dimension throughout.
std::optional<int> reference_dimension(const SweepPlan& plan, const StatePoints& s,
                                       std::size_t axis, const std::vector<TaskResult>& results) {
  if (plan.kind() != TaskKind::run || s.axes[axis] != "phi") return std::nullopt;
  std::optional<int> dimension;
  for (const TaskResult& r : results) {
    if (r.status != TaskStatus::done) continue;
    if (dimension && *dimension != r.dimension) return std::nullopt;
    dimension = r.dimension;
  }
  if (dimension != 2 && dimension != 3) return std::nullopt;
  return dimension;
}

std::string reference_name(int dimension) {
  return dimension == 2 ? "Henderson (hard disks)" : "Kolafa-Labik-Malijevsky (hard spheres)";
}

// Round tick values covering [low, high]: about five, never more than kMostTicks. Counted by
// index, not by adding steps: a step below what a double resolves at `low` (axis values a
// rounding apart, 0.3 and 0.1 + 0.2) leaves a sum where it was, and the loop never ended.
std::vector<double> ticks(double low, double high) {
  constexpr double kMostTicks = 12;
  const double span = high - low;
  if (!(span > 0.0) || !std::isfinite(span)) return {};
  const double raw = span / 5.0;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = magnitude;
  for (double factor : {2.0, 5.0, 10.0}) {
    if (raw > step) step = magnitude * factor;
  }
  const double first = std::ceil(low / step), last = std::floor(high / step + 1e-9);
  if (!(last - first >= 0.0 && last - first <= kMostTicks)) return {low, high};
  std::vector<double> values;
  for (int i = 0; i <= static_cast<int>(last - first); ++i) {
    const double t = (first + i) * step;
    values.push_back(std::abs(t) < step * 1e-9 ? 0.0 : t);
  }
  return values;
}

constexpr const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                                    "#ff7f0e", "#17becf", "#8c564b", "#e377c2"};

// One chart: the measure's estimates against the x axis, a series for each value of the other
// axes, and the reference curve if given.
std::string chart(const StatePoints& s, std::size_t axis, std::size_t measure,
                  std::optional<int> reference) {
  constexpr double kWidth = 560, kHeight = 340, kLeft = 70, kRight = 20, kTop = 20, kBottom = 50;
  std::vector<std::string> series;
  std::unordered_map<std::string, std::size_t> index_of_series;  // hashed: 100,000 points
  std::vector<std::size_t> series_of;
  double x_low = INFINITY, x_high = -INFINITY, y_low = INFINITY, y_high = -INFINITY;
  for (const sweep::StatePoint& p : s.points) {
    std::string name;
    for (std::size_t a = 0; a < s.axes.size(); ++a) {
      if (a != axis)
        name += fmt::format("{}{} = {}", name.empty() ? "" : ", ", s.axes[a], p.values[a]);
    }
    const auto [found, added] = index_of_series.emplace(name, series.size());
    series_of.push_back(found->second);
    if (added) series.push_back(std::move(name));
    const double x = *number(p.values[axis]);
    x_low = std::min(x_low, x);
    x_high = std::max(x_high, x);
    const Estimate& e = p.estimates[measure];
    if (!std::isfinite(e.mean)) continue;
    const double bar = std::isfinite(e.error) ? e.error : 0.0;
    y_low = std::min(y_low, e.mean - bar);
    y_high = std::max(y_high, e.mean + bar);
  }
  if (!(y_low <= y_high)) return "<p>Nothing measured yet.</p>\n";
  const auto curve = [&](double x) { return *hard_particle_z(*reference, x); };
  if (reference) {
    y_low = std::min({y_low, curve(x_low), curve(x_high)});
    y_high = std::max({y_high, curve(x_low), curve(x_high)});
  }
  const double x_pad = x_high > x_low ? 0.05 * (x_high - x_low) : 0.5;
  const double y_pad =
      y_high > y_low ? 0.08 * (y_high - y_low) : std::max(1e-12, 0.1 * std::abs(y_high));
  x_low -= x_pad, x_high += x_pad, y_low -= y_pad, y_high += y_pad;
  const auto px = [&](double x) {
    return kLeft + (x - x_low) / (x_high - x_low) * (kWidth - kLeft - kRight);
  };
  const auto py = [&](double y) {
    return kHeight - kBottom - (y - y_low) / (y_high - y_low) * (kHeight - kTop - kBottom);
  };

  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} "
      "{1}\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"{0}\" height=\"{1}\" "
      "fill=\"white\"/>\n"
      "<rect x=\"{2}\" y=\"{3}\" width=\"{4}\" height=\"{5}\" fill=\"none\" stroke=\"#888\"/>\n",
      kWidth, kHeight, kLeft, kTop, kWidth - kLeft - kRight, kHeight - kTop - kBottom);
  for (double t : ticks(x_low, x_high)) {
    svg += fmt::format(
        "<line x1=\"{0:.1f}\" y1=\"{1}\" x2=\"{0:.1f}\" y2=\"{2}\" stroke=\"#888\"/><text "
        "x=\"{0:.1f}\" y=\"{3}\" text-anchor=\"middle\">{4:g}</text>\n",
        px(t), kHeight - kBottom, kHeight - kBottom + 5, kHeight - kBottom + 18, t);
  }
  for (double t : ticks(y_low, y_high)) {
    svg += fmt::format(
        "<line x1=\"{0}\" y1=\"{1:.1f}\" x2=\"{2}\" y2=\"{1:.1f}\" stroke=\"#888\"/><text "
        "x=\"{3}\" y=\"{4:.1f}\" text-anchor=\"end\">{5:.6g}</text>\n",
        kLeft - 5, py(t), kLeft, kLeft - 8, py(t) + 4, t);
  }
  svg += fmt::format(
      "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n<text x=\"15\" y=\"{}\" "
      "text-anchor=\"middle\" transform=\"rotate(-90 15 {})\">{}</text>\n",
      (kLeft + kWidth - kRight) / 2, kHeight - 12, escaped(s.axes[axis]),
      (kTop + kHeight - kBottom) / 2, (kTop + kHeight - kBottom) / 2, escaped(s.measures[measure]));
  if (reference) {
    std::string points;
    for (int i = 0; i <= 100; ++i) {
      const double x = x_low + (x_high - x_low) * i / 100.0;
      points += fmt::format("{:.1f},{:.1f} ", px(x), py(curve(x)));
    }
    svg += fmt::format(
        "<polyline class=\"reference\" points=\"{}\" fill=\"none\" stroke=\"#555\" "
        "stroke-dasharray=\"5,4\"/>\n",
        points);
  }
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    const Estimate& e = s.points[i].estimates[measure];
    if (!std::isfinite(e.mean)) continue;
    const char* colour = kColours[series_of[i] % std::size(kColours)];
    const double x = px(*number(s.points[i].values[axis]));
    if (std::isfinite(e.error)) {
      svg += fmt::format(
          "<line class=\"error-bar\" x1=\"{0:.1f}\" y1=\"{1:.1f}\" x2=\"{0:.1f}\" y2=\"{2:.1f}\" "
          "stroke=\"{3}\"/>\n",
          x, py(e.mean - e.error), py(e.mean + e.error), colour);
    }
    svg += fmt::format(
        "<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"3.5\" fill=\"{}\"><title>{} = {}: {} = {} &#177; "
        "{}</title></circle>\n",
        x, py(e.mean), colour, escaped(s.axes[axis]), escaped(s.points[i].values[axis]),
        escaped(s.measures[measure]), e.mean, e.error);
  }
  // The legend: the series (when there are several) and the reference.
  double y = kTop + 16;
  for (std::size_t k = 0; k < series.size() && !series[k].empty(); ++k, y += 16) {
    svg += fmt::format(
        "<circle cx=\"{}\" cy=\"{}\" r=\"3.5\" fill=\"{}\"/><text x=\"{}\" y=\"{}\">{}</text>\n",
        kLeft + 14, y - 4, kColours[k % std::size(kColours)], kLeft + 24, y, escaped(series[k]));
  }
  if (reference) {
    svg += fmt::format(
        "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#555\" "
        "stroke-dasharray=\"5,4\"/><text x=\"{}\" y=\"{}\">{}</text>\n",
        kLeft + 6, y - 4, kLeft + 22, y - 4, kLeft + 24, y, reference_name(*reference));
  }
  return svg + "</svg>\n";
}

// Whether a measure says more than its axis: not the same at every point (the temperature of
// runs at a fixed kT), nor the axis itself (the packing fraction against phi), to rounding.
bool worth_drawing(const StatePoints& s, std::size_t axis, std::size_t measure) {
  constexpr double kRounding = 1e-9;
  bool constant = true, the_axis = true;
  const double first = s.points.front().estimates[measure].mean;
  for (const sweep::StatePoint& p : s.points) {
    const double y = p.estimates[measure].mean, x = *number(p.values[axis]);
    if (!std::isfinite(y)) continue;
    constant = constant && std::abs(y - first) <= kRounding * std::abs(first);
    the_axis = the_axis && std::abs(y - x) <= kRounding * std::abs(x);
  }
  return !constant && !the_axis;
}

std::string value_or_blank(double x) {
  return std::isfinite(x) ? fmt::format("{:.6g}", x) : "";
}

}  // namespace

void write_sweep_report(std::ostream& out, const SweepPlan& plan,
                        const std::vector<TaskResult>& results) {
  const StatePoints s = sweep::state_points(plan, results);
  std::size_t done = 0;
  for (const TaskResult& r : results) done += r.status == TaskStatus::done ? 1 : 0;
  out << "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>carom sweep: "
      << escaped(plan.name()) << "</title>\n<style>body{font-family:sans-serif;margin:2em;"
      << "max-width:64em}table{border-collapse:collapse}td,th{padding:2px 8px;text-align:right;"
      << "border-bottom:1px solid #ddd}pre{background:#f4f4f4;padding:1em}"
      << "figure{display:inline-block;margin:0 1em 1em 0}.drifted,.warned{color:#b00;font-weight:bold}"
      << "</style></head><body>\n";
  out << fmt::format("<h1>carom sweep: {}</h1>\n<p>{} of {} tasks done.</p>\n",
                     escaped(plan.name()), done, results.size());

  const std::optional<std::size_t> axis = x_axis(s);
  const std::optional<int> reference =
      axis ? reference_dimension(plan, s, *axis, results) : std::nullopt;
  if (axis) {
    out << "<h2>Measures</h2>\n<p>Each point is the mean over the seeds of a state point, its "
           "bar the standard error of that mean (with one seed, the run's own block-average "
           "error).</p>\n";
    for (std::size_t m = 0; m < s.measures.size(); ++m) {
      if (!worth_drawing(s, *axis, m)) continue;
      out << "<figure>" << chart(s, *axis, m, s.measures[m] == "Z" ? reference : std::nullopt)
          << "<figcaption>" << escaped(s.measures[m]) << "</figcaption></figure>\n";
    }
  }

  out << "<h2>State points</h2>\n<table><tr>";
  for (const std::string& a : s.axes) out << "<th>" << escaped(a) << "</th>";
  out << "<th>done</th>";
  for (const std::string& m : s.measures) out << "<th>" << escaped(m) << "</th><th>error</th>";
  if (reference) out << "<th>" << reference_name(*reference) << "</th><th>Z - it, in errors</th>";
  if (s.drift_measured) out << "<th>Z drifted</th>";
  out << "</tr>\n";
  const std::size_t z = static_cast<std::size_t>(
      std::find(s.measures.begin(), s.measures.end(), "Z") - s.measures.begin());
  for (const sweep::StatePoint& p : s.points) {
    out << "<tr>";
    for (const std::string& v : p.values) out << "<td>" << escaped(v) << "</td>";
    out << fmt::format("<td>{} of {}</td>", p.done, p.tasks);
    for (const Estimate& e : p.estimates) {
      out << "<td>" << value_or_blank(e.mean) << "</td><td>" << value_or_blank(e.error) << "</td>";
    }
    if (reference) {
      const double expected = *hard_particle_z(*reference, *number(p.values[*axis]));
      const Estimate& e = p.estimates[z];
      out << "<td>" << value_or_blank(expected) << "</td><td>"
          << value_or_blank((e.mean - expected) / e.error) << "</td>";
    }
    if (s.drift_measured) {
      out << (p.drifted > 0 ? fmt::format("<td class=\"drifted\">{} of {}</td>", p.drifted, p.done)
                            : std::string("<td></td>"));
    }
    out << "</tr>\n";
  }
  out << "</table>\n";

  std::string failures;
  for (std::size_t i = 0; i < results.size(); ++i) {
    if (results[i].status == TaskStatus::failed) {
      failures += fmt::format("<li><b>{}</b>: {}</li>\n", escaped(plan.tasks()[i].name),
                              escaped(results[i].error));
    }
  }
  if (!failures.empty()) out << "<h2>Failed tasks</h2>\n<ul>\n" << failures << "</ul>\n";
  std::string drifting;
  for (std::size_t i = 0; i < results.size(); ++i) {
    if (results[i].status == TaskStatus::done && drifted(results[i])) {
      drifting += fmt::format("<li><b>{}</b>: {:.1f} standard errors</li>\n",
                              escaped(plan.tasks()[i].name), results[i].measure(kDriftMeasure));
    }
  }
  if (!drifting.empty()) {
    out << "<h2 class=\"drifted\">Tasks whose Z drifted</h2>\n<p>Z moved between the first and "
           "the second half of these runs' measurement windows by more than "
        << DriftVerdict::kWarning
        << " standard errors: they were still changing while measured, and their state points' "
           "numbers are not equilibrium values. Equilibrate them longer.</p>\n<ul>\n"
        << drifting << "</ul>\n";
  }
  std::string correlated;
  for (std::size_t i = 0; i < results.size(); ++i) {
    if (results[i].status == TaskStatus::done && !drifted(results[i]) &&
        blocks_correlated(results[i])) {
      correlated += fmt::format("<li><b>{}</b>: {:.2f}</li>\n", escaped(plan.tasks()[i].name),
                                results[i].measure(kCorrelationMeasure));
    }
  }
  if (!correlated.empty()) {
    out << "<h2 class=\"warned\">Tasks whose Z fluctuated over longer than a block</h2>\n<p>The "
           "blocks of these runs' measurement windows are correlated (column "
        << kCorrelationMeasure << ": their lag-one autocorrelation, in units of the spread of "
        << "independent blocks', above " << DriftVerdict::kCorrelationWarning
        << "): Z remembers itself from one block to the next, so the errors over the blocks "
           "understate the uncertainty. Measure over a longer window, or compare seeds.</p>\n"
           "<ul>\n"
        << correlated << "</ul>\n";
  }
  out << "<h2>The plan</h2>\n<pre>" << escaped(plan.text()) << "</pre>\n</body></html>\n";
}

}  // namespace carom
