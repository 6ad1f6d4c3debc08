#include "host/study/stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hmp::study {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::size_t items_of(const RankTable& ranks) { return ranks.empty() ? 0 : ranks.front().size(); }

// Mid-ranks 1…k of one participant's values (ties share the mean of the places they cover).
std::vector<double> mid_ranks(const std::vector<double>& v) {
  std::vector<double> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    double below = 0, equal = 0;
    for (const double w : v) {
      below += w < v[i] ? 1 : 0;
      equal += w == v[i] ? 1 : 0;
    }
    out[i] = below + (equal + 1) / 2;
  }
  return out;
}

// Series of the lower regularized gamma P(a, x), for x < a + 1.
double lower_gamma_series(double a, double x) {
  double term = 1 / a, sum = term;
  for (int n = 1; n < 1000; ++n) {
    term *= x / (a + n);
    sum += term;
    if (std::fabs(term) < std::fabs(sum) * 1e-16) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

// Continued fraction of the upper regularized gamma Q(a, x), for x ≥ a + 1 (modified Lentz).
double upper_gamma_fraction(double a, double x) {
  const double tiny = 1e-300;
  double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
  for (int i = 1; i < 1000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::fabs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1 / d;
    const double delta = d * c;
    h *= delta;
    if (std::fabs(delta - 1) < 1e-16) break;
  }
  return h * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

}  // namespace

std::vector<std::vector<int>> pairwise_preferences(const RankTable& ranks) {
  const std::size_t k = items_of(ranks);
  std::vector<std::vector<int>> prefer(k, std::vector<int>(k, 0));
  for (const auto& row : ranks) {
    for (std::size_t i = 0; i < k; ++i) {
      for (std::size_t j = 0; j < k; ++j) prefer[i][j] += row[i] < row[j] ? 1 : 0;
    }
  }
  return prefer;
}

CopelandResult copeland(const RankTable& ranks) {
  const std::size_t k = items_of(ranks);
  const auto prefer = pairwise_preferences(ranks);
  CopelandResult c;
  c.score.assign(k, 0);
  c.wins.assign(k, 0);
  c.losses.assign(k, 0);
  c.ties.assign(k, 0);
  for (std::size_t i = 0; i < k; ++i) {
    for (std::size_t j = 0; j < k; ++j) {
      if (i == j) continue;
      if (prefer[i][j] > prefer[j][i])
        ++c.wins[i];
      else if (prefer[i][j] < prefer[j][i])
        ++c.losses[i];
      else
        ++c.ties[i];
    }
    c.score[i] = c.wins[i] - c.losses[i];
  }
  if (k == 0) return c;
  const int best = *std::max_element(c.score.begin(), c.score.end());
  for (std::size_t i = 0; i < k; ++i) {
    if (c.score[i] == best) c.winners.push_back(static_cast<int>(i));
  }
  return c;
}

std::vector<int> first_place_votes(const RankTable& ranks) {
  std::vector<int> votes(items_of(ranks), 0);
  for (const auto& row : ranks) {
    if (row.empty()) continue;
    const double best = *std::min_element(row.begin(), row.end());
    for (std::size_t i = 0; i < row.size(); ++i) votes[i] += row[i] == best ? 1 : 0;
  }
  return votes;
}

FriedmanResult friedman(const RankTable& ranks) {
  const std::size_t k = items_of(ranks);
  const double n = static_cast<double>(ranks.size());
  FriedmanResult f;
  f.df = k > 0 ? static_cast<int>(k) - 1 : 0;
  if (ranks.size() < 2 || k < 2) {
    f.chi2 = f.p = f.kendall_w = kNaN;
    return f;
  }
  std::vector<double> sums(k, 0);
  double tie_sum = 0;  // Σ over participants and tie groups of t³ − t
  for (const auto& row : ranks) {
    const std::vector<double> r = mid_ranks(row);
    for (std::size_t j = 0; j < k; ++j) sums[j] += r[j];
    std::vector<double> sorted = row;
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t i = 0; i < k;) {
      std::size_t e = i;
      while (e < k && sorted[e] == sorted[i]) ++e;
      const double t = static_cast<double>(e - i);
      tie_sum += t * t * t - t;
      i = e;
    }
  }
  const double kk = static_cast<double>(k);
  const double mean = n * (kk + 1) / 2;
  double s = 0;
  for (const double r : sums) s += (r - mean) * (r - mean);
  const double correction = 1 - tie_sum / (n * kk * (kk * kk - 1));
  if (correction <= 0) {
    f.chi2 = f.p = f.kendall_w = kNaN;
    return f;
  }
  f.chi2 = 12 * s / (n * kk * (kk + 1)) / correction;
  f.p = chi_square_sf(f.chi2, f.df);
  f.kendall_w = f.chi2 / (n * (kk - 1));
  return f;
}

double chi_square_sf(double x, int df) {
  if (df <= 0 || std::isnan(x)) return kNaN;
  if (x <= 0) return 1;
  const double a = df / 2.0, half = x / 2;
  if (half < a + 1) return 1 - lower_gamma_series(a, half);
  return upper_gamma_fraction(a, half);
}

}  // namespace hmp::study
