// The sweep's report page and the equations of state it draws.
#include <gtest/gtest.h>

#include <sstream>

#include "carom/core/equation_of_state.hpp"
#include "carom/sweep/sweep.hpp"

namespace carom {
namespace {

std::string plan_text(int dimension, const std::string& axis) {
  const std::string phi = axis.rfind("phi", 0) == 0 ? "" : "phi = 0.2\n";
  const std::string n = axis.rfind("n ", 0) == 0 ? "" : "n = 64\n";
  return "# a <comment> & more\n[start]\n" + n + phi + "dim = " + std::to_string(dimension) +
         "\n[run]\nend_time = 5\n[sweep]\n" + axis + "\nseed = [1, 2]\n";
}

// Tasks whose Z is `z` and its own error 0.1, of `dimension`, the last one failed.
std::vector<TaskResult> results_of(const SweepPlan& plan, int dimension) {
  std::vector<TaskResult> results;
  for (std::size_t i = 0; i < plan.tasks().size(); ++i) {
    TaskResult r = TaskResult::with(TaskStatus::done);
    r.dimension = dimension;
    r.measures = {{"Z", 2.0 + 0.5 * static_cast<double>(i)},
                  {"Z_error", 0.1},
                  {"pressure", 1.0 + static_cast<double>(i)},
                  {"temperature", 1.0}};
    results.push_back(r);
  }
  results.back() = TaskResult::with(TaskStatus::failed, "no <room> left");
  return results;
}

std::string page(const std::string& text, int dimension) {
  const SweepPlan plan = SweepPlan::parse(text, "plan.toml", ".");
  std::ostringstream out;
  write_sweep_report(out, plan, results_of(plan, dimension));
  return out.str();
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) {
    ++n;
  }
  return n;
}

TEST(SweepReport, DrawsEachMeasureWithAnErrorBarAPointAndTheEquationOfStateBesideZ) {
  // phi 0.3 and 0.4, seeds 1 and 2: two state points; the last task failed.
  const std::string html = page(plan_text(2, "phi = [0.3, 0.4]"), 2);
  // Z and pressure are drawn; the temperature, the same at every point, is not.
  EXPECT_EQ(count(html, "<svg"), 2u);
  EXPECT_EQ(count(html, "class=\"error-bar\""), 3u);  // Z: two means of two; the last has one
  EXPECT_EQ(count(html, "class=\"reference\""), 1u);
  EXPECT_NE(html.find("Henderson (hard disks)"), std::string::npos);
  // Z at phi 0.3: the mean of 2 and 2.5, 2.25 +- 0.25; at 0.4 one task: 3 +- its own 0.1.
  EXPECT_NE(html.find("phi = 0.3: Z = 2.25 &#177; 0.25"), std::string::npos);
  EXPECT_NE(html.find("phi = 0.4: Z = 3 &#177; 0.1"), std::string::npos);
  EXPECT_NE(html.find("<li><b>phi=0.4,seed=2</b>: no &lt;room&gt; left</li>"), std::string::npos);
  EXPECT_NE(html.find("# a &lt;comment&gt; &amp; more"), std::string::npos);
  EXPECT_EQ(html.find("<comment>"), std::string::npos);
}

TEST(SweepReport, TheReferenceIsTheDimensionsAndOnlyAgainstPhi) {
  EXPECT_NE(page(plan_text(3, "phi = [0.3, 0.4]"), 3).find("Kolafa-Labik-Malijevsky"),
            std::string::npos);
  const std::string against_n = page(plan_text(2, "n = [64, 100]"), 2);
  EXPECT_EQ(against_n.find("class=\"reference\""), std::string::npos);
  EXPECT_EQ(count(against_n, "<svg"), 2u);
  // Nothing numeric to draw against: a table only.
  const std::string against_rule = page(plan_text(2, "rule = [\"swap\", \"elastic\"]"), 2);
  EXPECT_EQ(count(against_rule, "<svg"), 0u);
  EXPECT_NE(against_rule.find("<td>elastic</td>"), std::string::npos);
}

// Axis values a rounding apart (0.3 and 0.1 + 0.2) draw a chart, in bounded
// time and memory (the tick loop advanced by less than a double resolves, forever).
TEST(SweepReport, NearEqualAxisValuesAreDrawnInBoundedTime) {
  for (const char* axis : {"phi = [0.3, 0.30000000000000004]", "phi = [0.1, 0.1000000000001]"}) {
    const std::string html = page(plan_text(2, axis), 2);
    EXPECT_EQ(count(html, "<svg"), 2u) << axis;
    EXPECT_LT(count(html, "<line"), 100u) << axis;
  }
}

TEST(EquationOfState, HendersonAndKolafaLabikMalijevskyAtKnownPackings) {
  EXPECT_NEAR(henderson_z(0.5), 4.1035, 5e-5);
  EXPECT_NEAR(henderson_z(0.3), 2.0628, 5e-5);
  EXPECT_NEAR(kolafa_labik_malijevsky_z(0.45), 9.4029, 5e-5);
  EXPECT_NEAR(kolafa_labik_malijevsky_z(0.2), 2.4094, 5e-5);
  EXPECT_EQ(hard_particle_z(2, 0.5), henderson_z(0.5));
  EXPECT_FALSE(hard_particle_z(4, 0.5).has_value());
}

}  // namespace
}  // namespace carom
