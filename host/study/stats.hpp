#pragma once
// The statistics of `hmp study analyze` (design §15; docs/study.md "Statistics"), on a rank table:
// ranks[p][j] is participant p's rank of item j, lower is better, equal values are ties.
#include <vector>

namespace hmp::study {

using RankTable = std::vector<std::vector<double>>;

// prefer[i][j]: how many participants rank i better than j (ties count for neither).
std::vector<std::vector<int>> pairwise_preferences(const RankTable& ranks);

// Copeland's method (as in the paper): item i beats j when more participants prefer i to j than j to
// i. Score = pairwise wins − pairwise losses (a tied pair counts 0). Winners: every item with the
// highest score (more than one = a tie, which the report states).
struct CopelandResult {
  std::vector<int> score;
  std::vector<int> wins, losses, ties;
  std::vector<int> winners;
};
CopelandResult copeland(const RankTable& ranks);

// Participants who put the item first (a shared first place gives each of the tied items a vote).
std::vector<int> first_place_votes(const RankTable& ranks);

// Friedman's test over participants (blocks) and items (treatments), ranks turned into mid-ranks per
// participant, corrected for ties; p from the chi-square distribution with k − 1 degrees of freedom.
// Kendall's W = chi2 / (n (k − 1)) (the tie-corrected coefficient of concordance). NaN when
// undefined (fewer than 2 participants or items, or every participant ties every item).
struct FriedmanResult {
  double chi2 = 0;
  int df = 0;
  double p = 0;
  double kendall_w = 0;
};
FriedmanResult friedman(const RankTable& ranks);

// P(X > x) for X chi-square with df degrees of freedom: the regularized upper incomplete gamma
// Q(df/2, x/2).
double chi_square_sf(double x, int df);

}  // namespace hmp::study
