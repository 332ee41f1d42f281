// The paper's Table 4 (tab:param_sensitivity): the spinner's constraint violation after 500
// iterations for contact stiffness k x stiction velocity v_s, measured here beside the paper's,
// with the paper's forward differences and with idto's analytic derivatives.

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "studies.hpp"

namespace idto::tradeoffs {
namespace {

constexpr double kStiffness[] = {2e2, 2e4, 2e6, 2e8};
constexpr double kStiction[] = {0.05, 0.01, 0.005, 0.001};
// The paper's Table 4, rows v_s (as kStiction), columns k (as kStiffness).
constexpr double kPaper[4][4] = {{6.1e-8, 2.5e-8, 7.2e-8, 2.8e-7},
                                 {2.8e-7, 2.3e-7, 3.0e-4, 2.8e-1},
                                 {4.2e-5, 2.7e-3, 1.0e-3, 3.2e-1},
                                 {1.3e-2, 7.2e-2, 1.1e0, 5.0e0}};
// The target for the analytic grid: at or below the paper in at least this many cells.
constexpr int kTargetCells = 12;

struct Cell {
  double norm{0.0};     // |h|_2 after the last iteration
  double squared{0.0};  // sum h^2 (= |h|^2), the violation idto reports
  double angle{0.0};    // spinner angle gained, rad
  double seconds{0.0};  // whole solve
  double fall{1.0};     // Σh² at 80% of the iterations / Σh² at the end
  int shifted{0};       // factorizations that needed the Levenberg-Marquardt shift
  int factorizations{0};
};

/// The 16 cells at the paper's Δ₀ (main) and the smallest and largest ‖h‖₂ over the Δ₀ spread.
struct Grid {
  std::string method;  // "forward differences", "analytic derivatives"
  Cell main[4][4], low[4][4], high[4][4];
  double seconds{0.0};
  int solves{0};
};

/// The spinner with k and v_s replaced; `weight_scale` multiplies every cost weight.
ProblemDefinition Problem(const ExampleConfig& config, double k, double vs, double weight_scale) {
  ProblemDefinition problem = config.problem;
  problem.contact.parameters.stiffness = k;
  problem.contact.parameters.stiction_velocity = vs;
  problem.Qq *= weight_scale;
  problem.Qv *= weight_scale;
  problem.R *= weight_scale;
  problem.Qfq *= weight_scale;
  problem.Qfv *= weight_scale;
  return problem;
}

Cell RunCell(const ExampleConfig& config, const ProblemDefinition& problem,
             const SolverOptions& options) {
  const SolveResult r = Solve(config, problem, options);
  Cell cell;
  cell.squared = r.summary.constraint_violation;
  cell.norm = std::sqrt(cell.squared);
  cell.angle = MeasureTask(config, problem, r.solution).value;
  cell.seconds = r.summary.solve_time;
  if (!r.summary.log.empty() && cell.squared > 0.0) {
    const size_t at = r.summary.log.size() * 4 / 5;
    cell.fall = r.summary.log[at].constraint_violation / cell.squared;
  }
  for (const IterationSummary& it : r.summary.log) {
    if (it.time_hessian > 0.0) {
      ++cell.factorizations;
      if (it.regularization > 0.0) ++cell.shifted;
    }
  }
  return cell;
}

// The third grid's method: idto's defaults at the paper's settings.
constexpr const char* kIdtoMethod = "analytic derivatives and constraint correction";

// The reference sums its cost without idto's 1/2: doubling every weight makes idto's cost,
// gradient and Hessian (and so the scaling D and the trust region) those of the reference.
constexpr double kPaperWeightScale = 2.0;

/// The 16 cells with the paper's settings `paper` at each initial trust radius of `radii`.
Grid RunGrid(const ExampleConfig& config, const SolverOptions& paper,
             const std::vector<double>& radii, const std::string& method) {
  Grid g;
  g.method = method;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      const ProblemDefinition doubled =
          Problem(config, kStiffness[c], kStiction[r], kPaperWeightScale);
      for (size_t i = 0; i < radii.size(); ++i) {
        SolverOptions options = paper;
        options.initial_trust_radius = radii[i];
        const Cell cell = RunCell(config, doubled, options);
        g.seconds += cell.seconds;
        ++g.solves;
        if (i == 0) {
          g.main[r][c] = g.low[r][c] = g.high[r][c] = cell;
        } else {
          if (cell.norm < g.low[r][c].norm) g.low[r][c] = cell;
          if (cell.norm > g.high[r][c].norm) g.high[r][c] = cell;
        }
      }
    }
  }
  return g;
}

const char* const kHeader[] = {"v_s (m/s) \\ k (N/m)", "2·10²", "2·10⁴", "2·10⁶", "2·10⁸"};

Table GridTable() {
  return Table(std::vector<std::string>(std::begin(kHeader), std::end(kHeader)));
}

std::string SettingsText(const Context& context, int iterations) {
  std::ostringstream md;
  md << "The paper (§6, Table 4) reports, for its spinner, the *constraint violation after 500 "
        "iterations* for four contact stiffnesses k and four stiction velocities v_s (all other "
        "parameters as in its Table 2: σ = 1 cm, μ = 0.5, v_d = 0.1 m/s, δt = 0.05 s, N = 40). "
        "The paper does not print the solver settings of that table. Its spinner "
        "configuration (the reference implementation's `examples/spinner/spinner.yaml`) uses "
        "Lagrange multipliers (`equality_constraints: true`), forward differences, Δ₀ = 10, "
        "Δ_max = 10⁵ and all convergence tolerances 0 (so every run does all its iterations); "
        "its solver accepts a step when ρ > 0, and its log records the violation as the "
        "Euclidean norm ‖h‖₂ of the unactuated generalized forces (`h.norm()`), while the "
        "paper's text for Fig. 5 calls the violation the sum of squares Σh² (idto's "
        "`constraint_violation`). The reference's spinner is not the one of idto's example: "
        "the paper's text leaves the geometry open, and the reference's model "
        "(`models/spinner_reference.urdf`, which lists the four differences) places the "
        "spinner so that the fingertip meets it about 56° off the finger's line, where "
        "idto's example (`models/spinner.urdf`) has the fingertip point at the spinner's "
        "centre; its fingertip, spinner inertia and joint damping differ too. The nominal "
        "velocity is the reference's in both (1 rad/s on the spinner: the rate of the nominal "
        "positions, `v_nom` in spinner.yaml). We ran `examples/spinner/spinner.yaml` with "
        "the reference's model, k and v_s "
        "replaced and those settings: `constraint_method = kLagrangeMultipliers`, forward "
        "differences, `initial_trust_radius = 10`, `max_trust_radius = 1e5`, "
        "`acceptance_ratio = 0`, `fixed_iterations = true`, "
     << iterations << " iterations, " << context.threads
     << " threads, and every cost weight doubled: the reference's cost has no ½, so doubling "
        "makes idto's cost, gradient and Hessian (and with them the scaling D and the trust "
        "region) the reference's. These two grids take the reference's step: the dogleg step as "
        "it is (`constraint_correction = 0`). We then ran the same grid again with idto's "
        "default derivatives, `derivative_method = kAnalytic` (exact ∂τ/∂q; section 3), "
        "everything else identical, and a third time with idto's defaults at those settings: "
        "analytic derivatives and the constraint correction (`constraint_correction = 0.5`, "
        "docs/solver.md \"Constraint correction\": a dogleg step short of the Newton step is "
        "moved onto the linearized constraints h + A p = 0).\n\n";
  if (context.quick) {
    md << "**Quick mode: " << iterations
       << " iterations, not the paper's 500; these numbers are not comparable with the "
          "paper's.**\n\n";
  }
  return md.str();
}

/// ‖h‖₂ of one grid beside the paper's numbers, with the Δ₀ spread in parentheses.
std::string NormTable(const Grid& g, const std::vector<double>& radii, int iterations) {
  Table table = GridTable();
  for (int r = 0; r < 4; ++r) {
    std::vector<std::string> row{Num(kStiction[r])};
    for (int c = 0; c < 4; ++c) {
      std::string cell = "**" + Sci(g.main[r][c].norm) + "**";
      if (radii.size() > 1) {
        cell += " (" + Sci(g.low[r][c].norm) + "–" + Sci(g.high[r][c].norm) + ")";
      }
      row.push_back(cell + " / " + Sci(kPaper[r][c]));
    }
    table.Row(row);
  }
  std::ostringstream md;
  md << "‖h‖₂ (N m) after " << iterations << " iterations, **" << g.method
     << "**: **idto** at Δ₀ = " << G(radii[0]);
  if (radii.size() > 1) {
    md << " (in parentheses: the smallest and largest over Δ₀ ∈ {";
    for (size_t i = 0; i < radii.size(); ++i) md << (i ? ", " : "") << Num(radii[i]);
    md << "}, to show how much a small change of settings moves the result)";
  }
  md << " / the paper's Table 4:\n\n" << table.Markdown() << "\n";
  return md.str();
}

/// x rounded to the two significant digits the tables print (the paper's precision).
double AsPrinted(double x) { return std::isfinite(x) ? std::stod(Sci(x)) : x; }

/// Cells where ‖h‖₂ (Δ₀ = 10, as printed) is at or below the paper's number.
int CellsAtOrBelowPaper(const Grid& g) {
  int count = 0;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      if (AsPrinted(g.main[r][c].norm) <= kPaper[r][c]) ++count;
    }
  }
  return count;
}

/// Cells where `a` ends below `b` (Δ₀ = 10).
int CellsBelow(const Grid& a, const Grid& b) {
  int count = 0;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) count += a.main[r][c].norm < b.main[r][c].norm;
  }
  return count;
}

std::string CountText(const Grid& forward, const Grid& analytic, const Grid& idto) {
  const int f = CellsAtOrBelowPaper(forward), a = CellsAtOrBelowPaper(analytic);
  const int i = CellsAtOrBelowPaper(idto);
  std::ostringstream md;
  md << "**Cells at or below the paper's number** (‖h‖₂ at Δ₀ = 10 as printed, two significant "
        "digits, ≤ the paper's): forward differences (the reference's step) "
     << f << " of 16, analytic derivatives (the reference's step) " << a
     << " of 16, analytic derivatives and constraint correction (idto's defaults) " << i
     << " of 16. The target for the analytic derivatives is at least " << kTargetCells
     << " of 16: **" << (i >= kTargetCells ? "met" : "not met") << "** with idto's defaults (" << i
     << " of 16; " << a << " of 16 with the reference's step). The analytic derivatives end "
     << "below forward differences in " << CellsBelow(analytic, forward)
     << " of 16 cells with the reference's step; with the correction, below the reference's step "
     << "(analytic) in " << CellsBelow(idto, analytic) << " of 16.\n\n";
  return md.str();
}

/// Which norm does the paper's table report? Compared where the paper's runs converged.
std::string WhichNormText(const Grid& g) {
  std::vector<double> log_ratio_norm, log_ratio_squared;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      if (kPaper[r][c] < 1e-6 && g.main[r][c].norm < 1e-6) {
        log_ratio_norm.push_back(std::abs(std::log10(g.main[r][c].norm / kPaper[r][c])));
        log_ratio_squared.push_back(std::abs(std::log10(g.main[r][c].squared / kPaper[r][c])));
      }
    }
  }
  if (log_ratio_norm.empty()) return "";
  const double worst_norm = *std::max_element(log_ratio_norm.begin(), log_ratio_norm.end());
  const double best_squared = *std::min_element(log_ratio_squared.begin(), log_ratio_squared.end());
  std::ostringstream md;
  md << "**Which violation the table reports.** In the " << log_ratio_norm.size()
     << " cells where both the paper and idto (" << g.method
     << ") end below 10⁻⁶, idto's ‖h‖₂ is within a factor " << Num(std::pow(10.0, worst_norm), 2)
     << " of the paper's number, and idto's Σh² is at least a factor "
     << Sci(std::pow(10.0, best_squared), 1) << " away from it. ";
  if (worst_norm < 1.0 && best_squared > 3.0) {
    md << "So the table reports ‖h‖₂ (as the reference implementation logs it), not Σh².";
  } else {
    md << "The comparison does not settle which norm the table reports.";
  }
  md << "\n\n";
  return md.str();
}

/// Σh² of both grids and of idto as a user runs it; angle and time; the shifted factorizations.
std::string DetailTables(const Grid& forward, const Grid& analytic, const Cell (&plain)[4][4],
                         const SolverOptions& ours, int iterations) {
  Table squared = GridTable(), task = GridTable();
  int shifted[2] = {0, 0};
  for (int r = 0; r < 4; ++r) {
    std::vector<std::string> row{Num(kStiction[r])}, task_row{Num(kStiction[r])};
    for (int c = 0; c < 4; ++c) {
      const Cell& f = forward.main[r][c];
      const Cell& a = analytic.main[r][c];
      row.push_back(Sci(f.squared) + " / " + Sci(a.squared) + " / " + Sci(plain[r][c].squared));
      task_row.push_back(Num(f.angle, 3) + " / " + Num(a.angle, 3) + " rad, " + Num(f.seconds, 2) +
                         " / " + Num(a.seconds, 2) + " s");
      shifted[0] += f.shifted;
      shifted[1] += a.shifted;
    }
    squared.Row(row);
    task.Row(task_row);
  }
  std::ostringstream md;
  md << "The same as Σh² (N² m², idto's `constraint_violation`): paper's settings with forward "
        "differences (the reference's step) / paper's settings with idto's defaults (analytic "
        "derivatives and constraint correction) / idto as a user runs it "
        "(the same model with spinner.yaml's own weights and solver section, analytic "
        "derivatives: Δ₀ = "
     << Num(ours.initial_trust_radius) << ", Δ_max = " << Num(ours.max_trust_radius)
     << ", η = " << Num(ours.acceptance_ratio) << "; " << iterations << " iterations exactly):\n\n"
     << squared.Markdown() << "\n";
  md << "Spinner angle gained (the nominal asks for 2 rad; idto-run's task criterion asks for "
        "≥ 1.5 rad) and solve time, paper's settings, forward differences (the reference's "
        "step) / idto's defaults:\n\n"
     << task.Markdown() << "\n";
  md << "Hessian factorizations that needed the Levenberg–Marquardt shift of docs/solver.md "
        "(\"When H is numerically indefinite\"), all 16 cells, paper's settings: "
     << shifted[0] << " with forward differences, " << shifted[1] << " with idto's "
     << "defaults.\n\n";
  return md.str();
}

/// How one grid compares with the paper's claims, computed from its numbers.
std::string Reading(const Grid& g, const std::vector<double>& radii) {
  const auto& m = g.main;
  int within10 = 0, lower = 0;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      const double ratio = m[r][c].norm / kPaper[r][c];
      if (ratio < 10.0 && ratio > 0.1) ++within10;
      if (ratio < 1.0) ++lower;
    }
  }
  std::ostringstream md;
  md << "**Reading the table (" << g.method << ").** " << within10
     << " of 16 cells are within a factor of 10 of the paper's number; idto's is lower in " << lower
     << " of 16. ";
  // The paper's two claims: (1) at v_s = 0.05 the solver does well up to k = 2e8; (2) lower v_s
  // degrades it, particularly for large k.
  int good_up_to = -1;
  for (int c = 0; c < 4 && m[0][c].norm < 1e-6; ++c) good_up_to = c;
  md << "At v_s = 0.05 m/s (the paper's default) the paper reaches ‖h‖₂ ≤ " << Sci(kPaper[0][3])
     << " for every k up to 2·10⁸ N/m; idto reaches ‖h‖₂ < 1e-6 ";
  if (good_up_to == 3) {
    md << "for every k as well. ";
  } else if (good_up_to >= 0) {
    md << "up to k = " << G(kStiffness[good_up_to]) << " N/m, and ends at "
       << Sci(m[0][good_up_to + 1].norm) << "–" << Sci(m[0][3].norm)
       << " for the stiffer contacts. ";
  } else {
    md << "for no k of this row. ";
  }
  int grows = 0;
  for (int c = 0; c < 4; ++c) {
    if (m[3][c].norm > m[0][c].norm) ++grows;
  }
  md << "Going from v_s = 0.05 to 0.001 m/s the violation grows in " << grows
     << " of the 4 stiffness columns (paper: 4 of 4; at k = 2·10² from " << Sci(kPaper[0][0])
     << " to " << Sci(kPaper[3][0]) << ", idto from " << Sci(m[0][0].norm) << " to "
     << Sci(m[3][0].norm) << "; at k = 2·10⁸ paper " << Sci(kPaper[0][3]) << " → "
     << Sci(kPaper[3][3]) << ", idto " << Sci(m[0][3].norm) << " → " << Sci(m[3][3].norm) << "). ";
  if (grows >= 3) {
    md << "The paper's conclusion carries over: lower stiction velocities make the problem "
          "harder to solve to a small violation";
    md << ((m[3][3].norm > m[3][0].norm) == (kPaper[3][3] > kPaper[3][0])
               ? ", and, as in the paper, more so at high stiffness."
               : "; unlike the paper, at v_s = 0.001 m/s the stiffest contact is not the worst "
                 "case here.");
  } else {
    md << "Unlike the paper, lowering v_s does not consistently increase the violation here.";
  }
  if (radii.size() > 1) {
    double widest = 0.0;
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) widest = std::max(widest, g.high[r][c].norm / g.low[r][c].norm);
    }
    md << " Changing only Δ₀ moves a cell by up to a factor " << Sci(widest, 2)
       << ", so the exact number is a property of the run as much as of the problem; read the "
          "table for its orders of magnitude and trends.";
  }
  int falling = 0, large = 0;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      if (m[r][c].norm < 1e-6) continue;
      ++large;
      if (m[r][c].fall > 10.0) ++falling;
    }
  }
  if (large > 0) {
    md << " Of the " << large << " cells that end above 1e-6, " << falling
       << " were still converging: their Σh² fell by more than 10× over the last 20% of the "
          "iterations.";
  }
  md << "\n\n";
  return md.str();
}

/// The summary's note: solve times and the range of ‖h‖₂ over a grid.
std::string GridNote(const Grid& g) {
  double fastest = 1e300, slowest = 0.0;
  int best_r = 0, best_c = 0, worst_r = 0, worst_c = 0;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      fastest = std::min(fastest, g.main[r][c].seconds);
      slowest = std::max(slowest, g.main[r][c].seconds);
      if (g.main[r][c].norm < g.main[best_r][best_c].norm) best_r = r, best_c = c;
      if (g.main[r][c].norm > g.main[worst_r][worst_c].norm) worst_r = r, worst_c = c;
    }
  }
  std::ostringstream note;
  note << g.method << ": every solve took " << Num(fastest, 2) << "–" << Num(slowest, 2)
       << " s and ‖h‖₂ at the end ranged from " << Sci(g.main[best_r][best_c].norm)
       << " (k = " << G(kStiffness[best_c]) << " N/m, v_s = " << G(kStiction[best_r]) << " m/s) to "
       << Sci(g.main[worst_r][worst_c].norm) << " (k = " << G(kStiffness[worst_c])
       << " N/m, v_s = " << G(kStiction[worst_r]) << " m/s)";
  return note.str();
}

/// Figure: ‖h‖₂ vs k, one line per v_s, idto (solid, bars: Δ₀ spread) and the paper's (dashed);
/// one panel per derivative method.
std::string Figure(const Context& context, const Grid* const grids[2], int iterations) {
  const std::string png = context.figure_dir + "/tradeoffs_sensitivity.png";
  // One y range for both panels, in whole decades.
  double lo = 1e300, hi = 0.0;
  for (int i = 0; i < 2; ++i) {
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) {
        for (double x : {grids[i]->low[r][c].norm, grids[i]->high[r][c].norm, kPaper[r][c]}) {
          if (x > 0.0) lo = std::min(lo, x), hi = std::max(hi, x);
        }
      }
    }
  }
  std::ostringstream gp;
  gp << GnuplotHeader(png, 1500, 680) << "set multiplot layout 1,2 title \"Spinner: constraint "
     << "violation |h|_2 after " << iterations
     << " iterations; solid: idto (bars: range over initial trust radii), dashed: paper Table "
        "4\"\n"
     << "set logscale xy\nset format y \"10^{%T}\"\n"
     << "set xtics (\"2·10^2\" 200, \"2·10^4\" 2e4, \"2·10^6\" 2e6, \"2·10^8\" 2e8)\n"
     << "set xrange [100:4e8]\nset yrange [" << std::pow(10.0, std::floor(std::log10(lo))) << ":"
     << std::pow(10.0, std::ceil(std::log10(hi))) << "]\n"
     << "set xlabel \"contact stiffness k (N/m)\"\nset ylabel \"|h|_2 (N m)\"\n"
     << "set key below horizontal maxcols 2 font \",9\" spacing 1.1\nset bmargin 9\n";
  const char* colors[] = {"#1b9e77", "#d95f02", "#7570b3", "#e7298a"};
  for (int i = 0; i < 2; ++i) {
    const Grid& g = *grids[i];
    const std::string data =
        context.data_dir + "/sensitivity_" + (i == 0 ? "forward" : "analytic") + ".csv";
    std::ofstream out(data);
    for (int c = 0; c < 4; ++c) {
      out << kStiffness[c];
      for (int r = 0; r < 4; ++r) {
        out << ',' << g.main[r][c].norm << ',' << kPaper[r][c] << ',' << g.low[r][c].norm << ','
            << g.high[r][c].norm;
      }
      out << '\n';
    }
    gp << "set title \"" << g.method << "\"\nplot ";
    for (int r = 0; r < 4; ++r) {
      const int col = 2 + 4 * r;
      gp << (r ? ", " : "") << GnuplotQuote(data) << " using 1:" << col << ":" << col + 2 << ":"
         << col + 3 << " with yerrorlines lw 2 pt 7 lc rgb \"" << colors[r]
         << "\" title \"v_s = " << kStiction[r] << " m/s, idto\", " << GnuplotQuote(data)
         << " using 1:" << col + 1 << " with linespoints lw 1 dt 2 pt 6 lc rgb \"" << colors[r]
         << "\" title \"v_s = " << kStiction[r] << " m/s, paper\"";
    }
    gp << "\n";
  }
  gp << "unset multiplot\n";
  if (!RunGnuplot(context.data_dir, "sensitivity", gp.str())) return "";
  return "![Spinner constraint violation vs stiffness, idto (forward differences with the "
         "reference's step; analytic derivatives with the constraint correction) and the "
         "paper](" +
         context.figure_link_prefix + "tradeoffs_sensitivity.png)\n\n";
}

const char* const kDifferencesText =
    "**Remaining differences from the paper's runs.** The dynamics and distance code (idto's own "
    "RNEA and analytic sphere distances, Drake's in the paper); the arithmetic of the "
    "constrained step (the reference forms λ from the normal equations A H⁻¹ Aᵀ in scaled "
    "variables with a dense LDLᵀ, idto solves the banded KKT system with refinement: the same "
    "step in exact arithmetic); the trust-region update after a rejected Newton step (idto "
    "shrinks to ¼‖D⁻¹p‖, Nocedal & Wright Alg. 4.1; the reference shrinks to ¼Δ); the ratio "
    "when both the predicted and the actual reduction are below 8.9e-13 (the reference sets "
    "ρ = 0.5; tried as a temporary switch in session 24, it left every analytic cell at Δ₀ = 10 "
    "as it is); the scaling (the reference clamps D ≤ 1, inactive here since every diagonal "
    "entry of H is at least 8); the iterate reported (the reference's log row of the last "
    "iteration holds ‖h‖₂ before that iteration's step); idto's Levenberg–Marquardt retry when "
    "the Hessian factorization fails (counted above); and the machine and thread count (the "
    "paper's 4 threads; idto's results do not depend on the thread count); and, in the third "
    "grid only, idto's constraint correction of dogleg steps, which the reference does "
    "not have.\n\n";

/// The grid at Δ₀ = 10 on idto's own spinner example, beside the reference model's counts.
std::string ExampleModelText(const Grid& forward, const Grid& analytic,
                             const Grid& reference_analytic, int iterations) {
  // analytic, reference_analytic: idto's defaults (analytic derivatives, constraint correction).
  std::ostringstream md;
  md << "**The same grid on idto's spinner example** (`models/spinner.urdf`, everything else "
        "as above; Δ₀ = 10 only), to show how much the model alone moves the table:\n\n"
     << NormTable(analytic, {10.0}, iterations) << "Cells at or below the paper's number: "
     << "forward differences (the reference's step) " << CellsAtOrBelowPaper(forward)
     << " of 16, idto's defaults " << CellsAtOrBelowPaper(analytic)
     << " of 16 (the reference's model: " << CellsAtOrBelowPaper(reference_analytic)
     << " of 16 with idto's defaults).\n\n";
  return md.str();
}

}  // namespace

StudyResult RunSensitivityStudy(const Context& context) {
  StudyResult result;
  result.id = "sensitivity";
  result.title = "Contact stiffness × stiction velocity: the paper's Table 4 on the spinner";
  // The paper's problem: the reference implementation's spinner model (spinner.yaml's nominal
  // velocity is the reference's, 1 rad/s on the spinner).
  const ExampleConfig config = LoadEditedExample(
      context, "spinner", {{"urdf: spinner.urdf", "urdf: spinner_reference.urdf"}});
  const ExampleConfig example = LoadExample(context, "spinner");
  const int iterations = context.quick ? 100 : 500;
  // Initial trust radii of the spread (the paper's value first); quick mode runs only that one.
  const std::vector<double> radii =
      context.quick ? std::vector<double>{10.0} : std::vector<double>{10.0, 1.0, 100.0};

  // The settings of the paper's spinner (the reference implementation's spinner.yaml:
  // equality_constraints: true, Delta0 = 10, Delta_max = 1e5, every convergence tolerance 0,
  // forward differences; its trust-region loop accepts a step when rho > 0).
  SolverOptions paper = config.solver;
  paper.constraint_method = ConstraintMethod::kLagrangeMultipliers;
  paper.derivative_method = DerivativeMethod::kForwardDifferences;
  paper.max_iterations = iterations;
  paper.fixed_iterations = true;  // exactly `iterations`, as with all tolerances at 0
  paper.max_trust_radius = 1e5;
  paper.acceptance_ratio = 0.0;
  paper.num_threads = context.threads;
  paper.constraint_correction = 0.0;  // the reference's step
  SolverOptions paper_analytic = paper;
  paper_analytic.derivative_method = DerivativeMethod::kAnalytic;
  // idto's defaults at the paper's settings: analytic derivatives and the constraint correction.
  SolverOptions paper_idto = paper_analytic;
  paper_idto.constraint_correction = SolverOptions().constraint_correction;
  // idto as a user runs it: spinner.yaml's weights and solver section, same iteration count.
  SolverOptions ours = config.solver;
  ours.max_iterations = iterations;
  ours.fixed_iterations = true;
  ours.num_threads = context.threads;

  const Grid forward = RunGrid(config, paper, radii, "forward differences");
  const Grid analytic = RunGrid(config, paper_analytic, radii, "analytic derivatives");
  const Grid idto = RunGrid(config, paper_idto, radii, kIdtoMethod);
  const Grid example_forward = RunGrid(example, paper, {10.0}, "forward differences");
  const Grid example_idto = RunGrid(example, paper_idto, {10.0}, kIdtoMethod);
  Cell plain[4][4];
  double plain_seconds = 0.0;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      plain[r][c] = RunCell(config, Problem(config, kStiffness[c], kStiction[r], 1.0), ours);
      plain_seconds += plain[r][c].seconds;
    }
  }

  std::ostringstream md;
  md << SettingsText(context, iterations) << NormTable(forward, radii, iterations)
     << NormTable(analytic, radii, iterations) << NormTable(idto, radii, iterations)
     << CountText(forward, analytic, idto) << WhichNormText(forward)
     << DetailTables(forward, idto, plain, ours, iterations) << Reading(forward, radii)
     << Reading(analytic, radii) << Reading(idto, radii)
     << ExampleModelText(example_forward, example_idto, idto, iterations) << kDifferencesText;
  result.notes.push_back("Contact stiffness and stiction velocity (spinner, paper's settings, " +
                         std::to_string(iterations) + " iterations): " + GridNote(forward) + "; " +
                         GridNote(idto) +
                         ". They are not speed knobs here, but they set how far a solve gets.");
  const double example_seconds = example_forward.seconds + example_idto.seconds;
  md << "Time of the "
     << forward.solves + analytic.solves + idto.solves + example_forward.solves +
            example_idto.solves + 16
     << " solves: "
     << Num(forward.seconds + analytic.seconds + idto.seconds + example_seconds + plain_seconds, 2)
     << " s (forward differences " << Num(forward.seconds, 2) << " s, analytic derivatives "
     << Num(analytic.seconds, 2) << " s, with the constraint correction " << Num(idto.seconds, 2)
     << " s, " << forward.solves << " solves each; idto's spinner example "
     << Num(example_seconds, 2) << " s; idto as a user runs it " << Num(plain_seconds, 2)
     << " s).\n\n";
  if (context.gnuplot) {
    const Grid* const grids[2] = {&forward, &idto};
    md << Figure(context, grids, iterations);
  }
  result.markdown = md.str();
  return result;
}

}  // namespace idto::tradeoffs
