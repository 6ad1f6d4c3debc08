// hmp study analyze's statistics (host/study/stats.hpp): Copeland against a brute-force reference on
// 1,000 random rank tables with ties; Friedman's chi-square, its p-value and Kendall's W against values
// worked out by hand (docs/study.md shows the formulas); the chi-square survival function against
// closed forms and textbook critical values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <utility>

#include "host/study/stats.hpp"

namespace {

using hmp::study::RankTable;

// Reference: each participant's ranking written out as ordered pairs "x above y", counted in a map;
// a pair's majority gives +1 to its winner and −1 to its loser; winners by exhaustive comparison.
struct Reference {
  std::vector<int> score;
  std::vector<int> winners;
};

Reference brute_force_copeland(const RankTable& table, int k) {
  std::map<std::pair<int, int>, int> above;
  for (const auto& row : table) {
    for (int x = 0; x < k; ++x) {
      for (int y = 0; y < k; ++y) {
        if (row[static_cast<std::size_t>(x)] < row[static_cast<std::size_t>(y)]) above[{x, y}] += 1;
      }
    }
  }
  Reference r;
  r.score.assign(static_cast<std::size_t>(k), 0);
  for (int x = 0; x < k; ++x) {
    for (int y = x + 1; y < k; ++y) {
      const int xy = above[{x, y}], yx = above[{y, x}];
      if (xy > yx) {
        ++r.score[static_cast<std::size_t>(x)];
        --r.score[static_cast<std::size_t>(y)];
      } else if (yx > xy) {
        ++r.score[static_cast<std::size_t>(y)];
        --r.score[static_cast<std::size_t>(x)];
      }
    }
  }
  for (int x = 0; x < k; ++x) {
    bool best = true;
    for (int y = 0; y < k; ++y)
      best = best && r.score[static_cast<std::size_t>(y)] <= r.score[static_cast<std::size_t>(x)];
    if (best) r.winners.push_back(x);
  }
  return r;
}

TEST(StudyCopeland, MatchesBruteForceOnRandomTablesWithTies) {
  std::mt19937 rng(20150615);
  int tables_with_tied_winners = 0, tables_with_tied_ranks = 0;
  for (int t = 0; t < 1000; ++t) {
    const int k = std::uniform_int_distribution<int>(2, 5)(rng);
    const int n = std::uniform_int_distribution<int>(1, 12)(rng);
    RankTable table;
    for (int p = 0; p < n; ++p) {
      std::vector<double> row;
      // Half the tables: strict rankings (as the study records); the others: ranks drawn with
      // repetition, i.e. ties inside a participant's ranking.
      if (t % 2 == 0) {
        for (int i = 0; i < k; ++i) row.push_back(i + 1);
        std::shuffle(row.begin(), row.end(), rng);
      } else {
        for (int i = 0; i < k; ++i) row.push_back(std::uniform_int_distribution<int>(1, k)(rng));
        std::vector<double> sorted = row;
        std::sort(sorted.begin(), sorted.end());
        tables_with_tied_ranks += std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end() ? 1 : 0;
      }
      table.push_back(row);
    }
    const auto got = hmp::study::copeland(table);
    const Reference want = brute_force_copeland(table, k);
    ASSERT_EQ(got.score, want.score) << "table " << t;
    ASSERT_EQ(got.winners, want.winners) << "table " << t;
    for (int i = 0; i < k; ++i) {
      const auto u = static_cast<std::size_t>(i);
      ASSERT_EQ(got.wins[u] + got.losses[u] + got.ties[u], k - 1);
    }
    tables_with_tied_winners += got.winners.size() > 1 ? 1 : 0;
  }
  // The sample really exercises ties (of winners, and inside rankings).
  EXPECT_GT(tables_with_tied_winners, 100);
  EXPECT_GT(tables_with_tied_ranks, 100);
}

TEST(StudyCopeland, PaperStyleExample) {
  // 5 participants rank (square, triangle, analogue): analogue first for 3, square first for 2.
  const RankTable t{{2, 3, 1}, {2, 3, 1}, {3, 2, 1}, {1, 3, 2}, {1, 2, 3}};
  const auto c = hmp::study::copeland(t);
  EXPECT_EQ(c.score, (std::vector<int>{0, -2, 2}));
  EXPECT_EQ(c.winners, (std::vector<int>{2}));
  EXPECT_EQ(hmp::study::first_place_votes(t), (std::vector<int>{2, 0, 3}));
  const auto prefer = hmp::study::pairwise_preferences(t);
  EXPECT_EQ(prefer[2][0], 3);
  EXPECT_EQ(prefer[0][2], 2);
  EXPECT_EQ(prefer[0][1], 4);
}

TEST(StudyCopeland, CycleIsAThreeWayTie) {
  // Condorcet's paradox: A>B>C, B>C>A, C>A>B → every pair 2:1 around a cycle, all scores 0.
  const RankTable t{{1, 2, 3}, {3, 1, 2}, {2, 3, 1}};
  const auto c = hmp::study::copeland(t);
  EXPECT_EQ(c.score, (std::vector<int>{0, 0, 0}));
  EXPECT_EQ(c.winners, (std::vector<int>{0, 1, 2}));
}

TEST(StudyFriedman, NoTiesByHand) {
  // Rank sums R = (5, 8, 11), n = 4, k = 3: Q = 12/(4·3·4)·(25+64+121) − 3·4·4 = 4.5;
  // df 2: p = exp(−Q/2); W = Q/(n(k−1)) = 0.5625 (= 12·S/(n²(k³−k)) with S = 18).
  const RankTable t{{1, 2, 3}, {1, 3, 2}, {1, 2, 3}, {2, 1, 3}};
  const auto f = hmp::study::friedman(t);
  EXPECT_NEAR(f.chi2, 4.5, 1e-12);
  EXPECT_EQ(f.df, 2);
  EXPECT_NEAR(f.p, 0.10539922456186433, 1e-12);
  EXPECT_NEAR(f.kendall_w, 0.5625, 1e-12);
}

TEST(StudyFriedman, TiesByHand) {
  // Mid-ranks (1,2,3), (1.5,1.5,3), (2,1,3): R = (4.5, 4.5, 9), S = 13.5, uncorrected Q = 4.5;
  // one tie of 2: correction 1 − 6/(3·3·8) = 11/12 → Q = 54/11; W = Q/6 = 9/11.
  const RankTable t{{1, 2, 3}, {1, 1, 3}, {2, 1, 3}};
  const auto f = hmp::study::friedman(t);
  EXPECT_NEAR(f.chi2, 54.0 / 11, 1e-12);
  EXPECT_NEAR(f.p, std::exp(-27.0 / 11), 1e-12);
  EXPECT_NEAR(f.kendall_w, 9.0 / 11, 1e-12);
}

TEST(StudyFriedman, FullAgreementAndDegenerateTables) {
  const RankTable agree(5, std::vector<double>{1, 2, 3});
  const auto f = hmp::study::friedman(agree);
  EXPECT_NEAR(f.chi2, 10.0, 1e-12);  // n(k−1)
  EXPECT_NEAR(f.kendall_w, 1.0, 1e-12);
  EXPECT_NEAR(f.p, std::exp(-5.0), 1e-12);
  // Four items, no agreement at all: every item's rank sum equal → Q = 0, p = 1, W = 0.
  const RankTable none{{1, 2, 3, 4}, {4, 3, 2, 1}};
  const auto g = hmp::study::friedman(none);
  EXPECT_NEAR(g.chi2, 0.0, 1e-12);
  EXPECT_NEAR(g.p, 1.0, 1e-12);
  EXPECT_EQ(g.df, 3);
  // Undefined: one participant; everybody ties everything.
  EXPECT_TRUE(std::isnan(hmp::study::friedman(RankTable{{1, 2, 3}}).chi2));
  EXPECT_TRUE(std::isnan(hmp::study::friedman(RankTable{{1, 1, 1}, {2, 2, 2}}).kendall_w));
  EXPECT_TRUE(std::isnan(hmp::study::friedman(RankTable{}).p));
}

TEST(StudyChiSquare, ClosedFormsAndCriticalValues) {
  for (double x : {0.01, 0.5, 1.0, 3.0, 7.5, 20.0, 60.0, 200.0}) {
    EXPECT_NEAR(hmp::study::chi_square_sf(x, 2), std::exp(-x / 2), 1e-14 + 1e-12 * std::exp(-x / 2)) << x;
    const double df4 = std::exp(-x / 2) * (1 + x / 2);
    EXPECT_NEAR(hmp::study::chi_square_sf(x, 4), df4, 1e-13 + 1e-10 * df4) << x;
    const double df1 = std::erfc(std::sqrt(x / 2));
    EXPECT_NEAR(hmp::study::chi_square_sf(x, 1), df1, 1e-13 + 1e-10 * df1) << x;
  }
  // Tabulated 5 % critical values.
  EXPECT_NEAR(hmp::study::chi_square_sf(3.841458820694124, 1), 0.05, 1e-10);
  EXPECT_NEAR(hmp::study::chi_square_sf(5.991464547107979, 2), 0.05, 1e-10);
  EXPECT_NEAR(hmp::study::chi_square_sf(18.307038053275146, 10), 0.05, 1e-10);
  EXPECT_EQ(hmp::study::chi_square_sf(0, 3), 1.0);
  EXPECT_EQ(hmp::study::chi_square_sf(-1, 3), 1.0);
  EXPECT_TRUE(std::isnan(hmp::study::chi_square_sf(1, 0)));
  EXPECT_GE(hmp::study::chi_square_sf(1e6, 2), 0.0);
}

}  // namespace
