// Synthetic stitch meshes for the scheduler's tests and benchmark, built row
// by row on a "front": the polyline of course edges whose loops are not yet
// knit through. Each new row replaces a run of the front's segments by its
// own top edges, so short rows, branches and shaping come out of the same
// few calls.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "planner/stitch_mesh/stitch_mesh.hpp"

namespace planner::fixtures {

// What a face of a new row does: how many front segments it knits through
// (1 or 2) and how many top edges it makes (1 or 2). A short-row end is a
// triangle: `left_end`/`right_end` on a row's first/last face.
struct FaceSpec {
  int in = 1;
  int out = 1;
};

class Builder {
 public:
  // A first row of `width` knit faces, cast on.
  explicit Builder(int width) {
    std::vector<std::uint32_t> bottom, top;
    for (int i = 0; i <= width; ++i) bottom.push_back(vertex(i, 0));
    front_ = bottom;
    height_ = 0;
    std::vector<FaceSpec> specs(static_cast<std::size_t>(width));
    add_row(0, specs);
  }

  // A row over front segments [first, first + sum(in)). A triangle end has
  // in = out = 1 and shares its outer vertex between bottom and top.
  // Returns the index of the first new top segment in the new front.
  int add_row(int first, const std::vector<FaceSpec>& specs, bool left_end = false,
              bool right_end = false) {
    ++height_;
    int consumed = 0, made = 0;
    for (const FaceSpec& f : specs) {
      consumed += f.in;
      made += f.out;
    }
    const auto b0 = static_cast<std::size_t>(first);
    std::vector<std::uint32_t> bottom(
        front_.begin() + static_cast<std::ptrdiff_t>(b0),
        front_.begin() + static_cast<std::ptrdiff_t>(b0) + consumed + 1);
    // Top vertices, spread over the bottom's x range.
    const double x0 = pos_[bottom.front()].x(), x1 = pos_[bottom.back()].x();
    std::vector<std::uint32_t> top;
    for (int i = 0; i <= made; ++i) {
      if (i == 0 && left_end) {
        top.push_back(bottom.front());
      } else if (i == made && right_end) {
        top.push_back(bottom.back());
      } else {
        top.push_back(vertex(x0 + (x1 - x0) * i / std::max(1, made), height_));
      }
    }
    int bi = 0, ti = 0;
    for (std::size_t k = 0; k < specs.size(); ++k) {
      const FaceSpec& f = specs[k];
      StitchFace face;
      const bool left_tri = left_end && k == 0;
      const bool right_tri = right_end && k + 1 == specs.size();
      for (int j = 0; j <= f.in; ++j)
        face.vertices.push_back(bottom[static_cast<std::size_t>(bi + j)]);
      for (int j = 0; j < f.in; ++j) face.roles.push_back(EdgeRole::CourseIn);
      if (right_tri) {
        // bottom-left, bottom-right (= top-right), top-left
        face.roles.push_back(EdgeRole::CourseOut);
        face.vertices.push_back(top[static_cast<std::size_t>(ti)]);
        face.roles.push_back(EdgeRole::Wale);
      } else {
        face.roles.push_back(EdgeRole::Wale);
        for (int j = f.out; j >= 0; --j) {
          if (j == 0 && left_tri) break;
          face.vertices.push_back(top[static_cast<std::size_t>(ti + j)]);
        }
        // Sides after the right wale: the top edges, then the left wale.
        for (int j = 0; j < f.out; ++j) face.roles.push_back(EdgeRole::CourseOut);
        if (!left_tri) face.roles.push_back(EdgeRole::Wale);
      }
      face.arcs.assign(face.vertices.size(), kNoArc);
      face.type = face.vertices.size() == 3 ? FaceType::ShortRow
                  : f.in == 2               ? FaceType::Decrease
                  : f.out == 2              ? FaceType::Increase
                                            : FaceType::Knit;
      mesh_.faces.push_back(std::move(face));
      bi += f.in;
      ti += f.out;
    }
    std::vector<std::uint32_t> next(front_.begin(),
                                    front_.begin() + static_cast<std::ptrdiff_t>(b0));
    next.insert(next.end(), top.begin(), top.end());
    next.insert(next.end(), front_.begin() + static_cast<std::ptrdiff_t>(b0) + consumed + 1,
                front_.end());
    front_ = std::move(next);
    return first;
  }

  int front_segments() const { return static_cast<int>(front_.size()) - 1; }

  // Adds `extra` segments to the right end of the front, at its height, with
  // no face below them: the row that knits through them casts them on.
  void extend_right(int extra) {
    const double x = pos_[front_.back()].x();
    for (int i = 1; i <= extra; ++i) front_.push_back(vertex(x + i, height_));
  }

  StitchMesh mesh() const {
    StitchMesh m = mesh_;
    m.positions = pos_;
    m.course_mm = 1.05;
    m.wale_mm = 2.875;
    return m;
  }

 private:
  std::uint32_t vertex(double x, double y) {
    pos_.emplace_back(x, y, 0.0);
    return static_cast<std::uint32_t>(pos_.size() - 1);
  }
  StitchMesh mesh_;
  std::vector<Eigen::Vector3d> pos_;
  std::vector<std::uint32_t> front_;
  int height_ = 0;
};

inline std::vector<FaceSpec> knits(int n) {
  return std::vector<FaceSpec>(static_cast<std::size_t>(n));
}

// W x H rectangle of knit faces.
inline StitchMesh rectangle(int width, int height) {
  Builder b(width);
  for (int r = 1; r < height; ++r) b.add_row(0, knits(width));
  return b.mesh();
}

// A fan of decreases onto one needle (the situation of anchor's stitch mesh,
// V037): a short row [triangle, increase, triangle] whose triangle ends are
// bound off onto the increase's two loops (the far triangle holds two loops,
// its stitch and the tuck of the turn), then a decrease joins those two
// loops. Stacked as they come, the decrease's needle would hold 2 + 3 loops.
inline StitchMesh decrease_fan(int rows_above) {
  Builder b(3);
  b.add_row(0, {FaceSpec{1, 1}, FaceSpec{1, 2}, FaceSpec{1, 1}}, true, true);
  b.add_row(1, {FaceSpec{2, 1}});
  for (int r = 0; r < rows_above; ++r) b.add_row(1, knits(1));
  return b.mesh();
}

// A decrease over two loops that each hold a stack: the far triangle of a
// short row (its stitch, the tuck of its turn and the tail of the short
// row's bound-off stitches: three loops) and the loop beside it, which took
// the tail of the first row's bound-off end (two loops).
inline StitchMesh stacked_decrease(int rows_above) {
  Builder b(6);
  b.add_row(0, {FaceSpec{}, FaceSpec{}, FaceSpec{}, FaceSpec{}}, true, true);
  b.add_row(3, {FaceSpec{2, 1}});
  for (int r = 0; r < rows_above; ++r) b.add_row(3, knits(1));
  return b.mesh();
}

// A trapezoid narrowing by a decrease at both ends of every other row.
inline StitchMesh trapezoid(int width, int height) {
  Builder b(width);
  int w = width;
  for (int r = 1; r < height; ++r) {
    if (r % 2 == 1 && w >= 6) {
      std::vector<FaceSpec> specs(static_cast<std::size_t>(w - 2));
      specs.front().in = 2;
      specs.back().in = 2;
      b.add_row(0, specs);
      w -= 2;
    } else {
      b.add_row(0, knits(w));
    }
  }
  return b.mesh();
}

// A shape widening by an increase at both ends of every other row.
inline StitchMesh widening(int width, int height) {
  Builder b(width);
  int w = width;
  for (int r = 1; r < height; ++r) {
    if (r % 2 == 1) {
      std::vector<FaceSpec> specs(static_cast<std::size_t>(w));
      specs.front().out = 2;
      specs.back().out = 2;
      b.add_row(0, specs);
      w += 2;
    } else {
      b.add_row(0, knits(w));
    }
  }
  return b.mesh();
}

// A ledge: `below` rows of `width` knit faces, then `above` rows `extra`
// faces wider on the right. The first wide row knits through the loops
// below and casts on its last `extra` faces (their bottom edges are on the
// sheet's boundary), at the far end from where the yarn waits.
inline StitchMesh ledge(int width, int extra, int below, int above) {
  Builder b(width);
  for (int r = 1; r < below; ++r) b.add_row(0, knits(width));
  b.extend_right(extra);
  for (int r = 0; r < above; ++r) b.add_row(0, knits(width + extra));
  return b.mesh();
}

// Short rows: a full row, then a short row ending in a triangle on the right
// (one side) or on both sides, then a full row over all of it; repeated.
inline StitchMesh short_rows(int width, int repeats, bool both_sides) {
  Builder b(width);
  b.add_row(0, knits(width));
  for (int k = 0; k < repeats; ++k) {
    const int inset = 3;
    if (both_sides) {
      b.add_row(inset, knits(width - 2 * inset), true, true);
    } else {
      b.add_row(0, knits(width - inset), false, true);
    }
    b.add_row(0, knits(width));
  }
  return b.mesh();
}

// Fig. 9: a base A with two branches B (left) and C (right) above it, a gap
// of bound-off loops between them.
inline StitchMesh y_shape(int width, int base_rows, int branch_width, int branch_rows) {
  Builder b(width);
  for (int r = 1; r < base_rows; ++r) b.add_row(0, knits(width));
  for (int r = 0; r < branch_rows; ++r) {
    b.add_row(0, knits(branch_width));
    b.add_row(width - branch_width, knits(branch_width));
  }
  return b.mesh();
}

// Fig. 10: two branches that each widen over the other's base, so whichever
// is knit first covers the needles holding the other's loops: no order works
// without a cut.
inline StitchMesh crossing_branches(int width, int branch_width, int rows) {
  Builder b(width);
  b.add_row(0, knits(width));
  int left_w = branch_width;
  int right_w = branch_width;
  for (int r = 0; r < rows; ++r) {
    std::vector<FaceSpec> left(static_cast<std::size_t>(left_w));
    left.back().out = 2;  // widen to the right
    b.add_row(0, left);
    ++left_w;
    std::vector<FaceSpec> right(static_cast<std::size_t>(right_w));
    right.front().out = 2;  // widen to the left
    b.add_row(b.front_segments() - right_w, right);
    ++right_w;
  }
  return b.mesh();
}

// A stand-in for the paper's bunny cover at the default gauge (about 8,000
// stitches): a body that widens, carries short rows on both sides and
// narrows again, then splits into two ears that narrow to their tips.
inline StitchMesh cover_like() {
  Builder b(70);
  int w = 70;
  for (int r = 1; r < 60; ++r) {
    if (r % 8 == 0) {
      b.add_row(4, knits(w - 8), true, true);  // short rows across the back
      b.add_row(0, knits(w));
    } else if (r < 24 && r % 2 == 1) {
      std::vector<FaceSpec> specs(static_cast<std::size_t>(w));
      specs.front().out = 2;
      specs.back().out = 2;
      b.add_row(0, specs);
      w += 2;
    } else if (r > 44 && r % 3 == 0) {
      std::vector<FaceSpec> specs(static_cast<std::size_t>(w - 2));
      specs.front().in = 2;
      specs.back().in = 2;
      b.add_row(0, specs);
      w -= 2;
    } else {
      b.add_row(0, knits(w));
    }
  }
  // Two ears, 30 wide, 40 rows, narrowing every fourth row.
  int ear = 30;
  int right_first = w - ear;
  int left_w = ear, right_w = ear;
  for (int r = 0; r < 40; ++r) {
    const bool narrow = r % 4 == 3 && left_w > 8;
    if (narrow) {
      std::vector<FaceSpec> specs(static_cast<std::size_t>(left_w - 2));
      specs.front().in = 2;
      specs.back().in = 2;
      b.add_row(0, specs);
      left_w -= 2;
      right_first -= 2;
      std::vector<FaceSpec> rspecs(static_cast<std::size_t>(right_w - 2));
      rspecs.front().in = 2;
      rspecs.back().in = 2;
      b.add_row(right_first, rspecs);
      right_w -= 2;
    } else {
      b.add_row(0, knits(left_w));
      b.add_row(right_first, knits(right_w));
    }
  }
  return b.mesh();
}

// A random shape for property tests: branches of the front that grow by
// plain rows, random increases and decreases, short rows on one or both
// sides, and splits into two branches; some branches stop (bound off).
inline StitchMesh random_shape(std::uint32_t seed, int steps = 40) {
  std::mt19937 rng(seed);
  auto uniform = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  const int width = uniform(4, 24);
  Builder b(width);
  struct Branch {
    int width;
    bool alive;
  };
  // The front, left to right: branches and gaps (widths of bound-off runs).
  std::vector<Branch> parts{{width, true}};
  auto first_segment = [&](std::size_t k) {
    int n = 0;
    for (std::size_t i = 0; i < k; ++i) n += parts[i].width;
    return n;
  };
  for (int step = 0; step < steps; ++step) {
    std::vector<std::size_t> alive;
    for (std::size_t i = 0; i < parts.size(); ++i) {
      if (parts[i].alive) alive.push_back(i);
    }
    if (alive.empty()) break;
    const std::size_t k =
        alive[static_cast<std::size_t>(uniform(0, static_cast<int>(alive.size()) - 1))];
    const int w = parts[k].width;
    const int first = first_segment(k);
    const int op = uniform(0, 9);
    if (op <= 2) {
      b.add_row(first, knits(w));
    } else if (op <= 4) {
      // Random shaping: each face may increase or decrease.
      std::vector<FaceSpec> specs;
      int used = 0;
      if (uniform(0, 1) == 0 && w < 40) {
        // Lean: widen on one side only, towards the neighbouring branches.
        specs.assign(static_cast<std::size_t>(w), FaceSpec{});
        (uniform(0, 1) == 0 ? specs.front() : specs.back()).out = 2;
        used = w;
      }
      while (used < w) {
        FaceSpec f;
        const int r = uniform(0, 9);
        if (r == 0 && used + 2 <= w && w - 1 >= 3) f.in = 2;
        if (r == 1 && w < 40) f.out = 2;
        used += f.in;
        specs.push_back(f);
      }
      int made = 0;
      for (const FaceSpec& f : specs) made += f.out;
      b.add_row(first, specs);
      parts[k].width = made;
    } else if (op <= 6 && w >= 6) {
      const bool both = uniform(0, 1) == 1;
      const int inset = uniform(1, (w - 2) / 2 - (both ? 1 : 0) > 1 ? (w - 2) / 2 - 1 : 1);
      if (both) {
        b.add_row(first + inset, knits(w - 2 * inset), true, true);
      } else if (uniform(0, 1) == 0) {
        b.add_row(first, knits(w - inset), false, true);
      } else {
        b.add_row(first + inset, knits(w - inset), true, false);
      }
      b.add_row(first, knits(w));
    } else if (op <= 8 && w >= 8) {
      // Split: left and right branches with a bound-off gap between.
      const int gap = uniform(0, 2);
      const int left = uniform(3, w - gap - 3);
      const int right = w - gap - left;
      b.add_row(first, knits(left));
      b.add_row(first + left + gap, knits(right));
      std::vector<Branch> replaced{{left, true}};
      if (gap > 0) replaced.push_back({gap, false});
      replaced.push_back({right, true});
      parts.erase(parts.begin() + static_cast<std::ptrdiff_t>(k));
      parts.insert(parts.begin() + static_cast<std::ptrdiff_t>(k), replaced.begin(),
                   replaced.end());
    } else if (alive.size() > 1) {
      parts[k].alive = false;  // this branch ends here
    } else {
      b.add_row(first, knits(w));
    }
  }
  return b.mesh();
}

}  // namespace planner::fixtures
