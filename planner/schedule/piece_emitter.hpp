// planner::PieceEmitter: the state of emit_piece (knitout_emit.hpp) while it
// writes one piece: the knitout so far, the loops on each needle, where the
// yarn hangs, the current carriage pass. Internal to the schedule stage:
//   knitout_emit.cpp  the piece's set-up, output, passes and time, machine
//                     operations with the loops they move, the yarn
//   emit_row.cpp      one row: transfers in, cast-on, two passes, bind-off
//                     (§7.4-7.5)
//   emit_tails.cpp    bind-off tails kept on the bed, and held loops set
//                     aside (§7.3, Schedule::aside_moves)
// Broken invariants throw std::logic_error.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "planner/schedule/knitout_emit.hpp"
#include "planner/schedule/schedule.hpp"
#include "planner/schedule/schoolbus.hpp"
#include "planner/stitch_mesh/stitch_mesh.hpp"

namespace planner {

class PieceEmitter {
 public:
  // `shift`: added to the schedule's needles to put the piece where
  // params.first_needle asks.
  PieceEmitter(const StitchMesh& mesh, const Schedule& s, const EmitParams& params, int shift)
      : mesh_(mesh), s_(s), params_(params), shift_(shift) {}

  EmittedPiece run(const Piece& piece);

 private:
  static constexpr int kTail = -2;  // the last loop of a bind-off chain
  // Loops one needle may hold (the swg091n2 profile's limit, V037): the
  // emitter keeps one token per physical loop and never goes beyond it.
  static constexpr std::size_t kMaxLoops = 4;
  static constexpr int kNoNeedle = 1 << 30;
  // The loop of a face between its passes.
  static int intermediate(int face) { return -(face + 10); }

  // ---- the piece (knitout_emit.cpp) ----
  // The rows (indices in this piece, ascending) that knit, tuck or land a
  // loop on each needle, and the held loops set aside before each row.
  std::vector<std::vector<AsideMove>> plan_piece(const Piece& piece);

  // ---- output ----
  void line(const std::string& text);
  void header();
  static std::string needle_name(char bed, int n) {
    return std::string(1, bed) + std::to_string(n);
  }

  // ---- passes and time ----
  struct PassKey {
    char kind = 0;  // 's' stitches, 'x' transfers, 'd' drops
    int direction = 0;
    int racking = 0;
    bool operator==(const PassKey&) const = default;
  };
  void touch(PassKey key, int n);
  void end_pass();

  // ---- machine operations, with the loops they move ----
  std::vector<int>& bed(char b, int n) { return b == 'f' ? front_[n] : back_[n]; }
  void rack(int r);
  void stitch(const char* op, int direction, char b, int n, int token);
  void xfer(char from_bed, int from, char to_bed, int to);
  // The yarn hangs from the last loop made, on (`bed`, `n`): a transfer of
  // that needle takes the yarn's end along (the next float is measured from
  // where it lands).
  static void follow_loop(char& bed, int& n, char from_bed, int from, char to_bed, int to);
  // A schoolbus plan's transfers, in a pass of their own, ending at racking 0.
  void make_transfers(const std::vector<Transfer>& plan);
  void move_loop(int from, int to);
  void drop(int n);
  // Every loop on front needle n now belongs to `token` (the loops of a
  // stack that are knit through together, or a chain's tail).
  void relabel(int n, int token);

  // ---- the yarn ----
  void bring_in();
  // Rather than float further than max_float_needles to `n`, the yarn goes
  // out and comes in again (the operator trims the ends).
  // `yarn_at`: where the yarn will hang from when the stitch at `n` is made
  // (the last loop's needle after any transfers in between).
  void cut_yarn_if_far(int n, int yarn_at);
  // Where the last loop made (and the yarn with it) will be once `plan`'s
  // transfers are made.
  int yarn_after(const std::vector<Transfer>& plan) const;
  void release_if_pending();

  // ---- bind-off tails and held loops set aside (emit_tails.cpp) ----
  // A bind-off tail on a needle this row needs moves to a needle needed
  // later or never (park); failing that it joins a live loop nearby
  // (holding_needle), or waits on a needle this row knits with room in the
  // stack, to be knit through with the stitch's loops, which holds its chain
  // as a holder would: its own (`knit_through`) or, when `elsewhere`,
  // another within the racking limit (`stay_`). Only when none of these
  // exists is it dropped (which lets its chain unravel: V053).
  // Returns the needle where the tail stays to be knit through, or kNoNeedle.
  int drop_tail(int n, bool knit_through, bool elsewhere);
  // The first row after row `after` that needs needle n (INT_MAX: none).
  int next_use(int n, int after) const;
  bool needed_later(int n) const;
  // Where a tail on `from` should wait after row `after`: among the needles
  // within the racking limit that are empty on both beds, the one whose next
  // use comes latest (never, best), nearest first, `prefer` side first on
  // ties; `from` itself when none is better.
  int parking_needle(int from, int after, int prefer, const std::set<int>* avoid = nullptr);
  // Where a tail on `from` that cannot wait on an empty needle can join a
  // live loop instead: the nearest front needle holding only live loops with
  // room for one more and nothing on the back, either untouched by the
  // current row (`row_needles_`), or one whose loops go to a single needle of
  // the row (`destination_`, possibly their own) that can take one more loop,
  // where the row's stitch knits the tail through. Within the racking limit
  // in one move; up to twice as far in two, through a needle empty on both
  // beds. `from` when none.
  struct Holder {
    int needle = 0;
    int via = kNoNeedle;  // the stop of a two-move way
  };
  Holder holding_needle(int from);
  // The loops still on this piece's bed move to their needles with one
  // schoolbus plan. A bind-off tail waiting on one of those needles moves
  // to an empty needle first, or stays to be carried on with the loop when
  // the stack has room; only when neither is possible is it dropped.
  void set_aside(const std::vector<AsideMove>& batch);

  // ---- one row (emit_row.cpp) ----
  int needle(int edge) const { return s_.edges[static_cast<std::size_t>(edge)].needle + shift_; }
  int work(int face) const { return needle(s_.faces[static_cast<std::size_t>(face)].out[0]); }
  bool loop_below(int edge) const;
  bool loop_above(int edge) const;
  bool is_triangle(int f) const;
  bool purl(int row_index, int pass, int n) const;

  void knit_row(int r, int row_index);
  // Transfers: every loop of the row's faces from where it was made to its
  // face's needle.
  std::vector<LoopMove> loops_in(const std::vector<int>& faces) const;
  // The current row's needles (arriving_, row_needles_, destination_,
  // stay_) for the tails' choices.
  void note_row_needles(const std::vector<int>& faces, const std::vector<LoopMove>& moves);
  // Bind-off tails on the needles the row needs are moved away first, or
  // kept to be knit through; returns the needles of the kept tails.
  std::vector<int> clear_tails(const std::vector<int>& faces);
  // The row's transfers, after knitting any stacks they would overfill.
  std::vector<Transfer> plan_row_transfers(const std::vector<LoopMove>& moves,
                                           const std::vector<int>& kept);
  // A decrease stacks the loops of its sources on one needle; a source may
  // already hold several (a short row's stitch and the tuck of its turn, a
  // loop that took bind-off tails). Where the stack would exceed kMaxLoops
  // the fullest sources are knit first, each into one loop, in one pass
  // before the transfers. A fan of more single loops than a needle holds
  // cannot be knit this way: a broken invariant.
  std::vector<int> consolidation(const std::vector<LoopMove>& moves);
  // Knits each of `knit` (needles holding stacks) into one loop, in one pass.
  void knit_stacks(std::vector<int> knit);
  // Every face's needle holds exactly its own loops once the transfers are
  // made, and the new needles of increases are empty.
  void check_row_needles(int r, const std::vector<int>& faces);
  // Cast-on (§7.5) of order[i, j): tucks out on every other face, back on
  // the rest; `pass_a_bed` puts them on the bed pass A knits (seed: purls
  // are on the back bed by then).
  void cast_on(const std::vector<int>& order, std::size_t i, std::size_t j, int dir, int row_index,
               bool pass_a_bed);
  // Seed pattern: the purls of pass `pass` to the back bed before it and
  // back to the front after it.
  void purls_to_back(const std::vector<int>& faces, int row_index, int pass);
  void purls_to_front(const std::vector<int>& faces, int row_index, int pass);
  // Pass A, the lower halves away from the start side (`order`: the row's
  // faces in that direction), with the cast-on of the faces marked in
  // `cast`; pass B, the upper halves back.
  void pass_a(const std::vector<int>& faces, const std::vector<int>& order,
              const std::vector<bool>& cast, int dir, int row_index);
  void pass_b(const std::vector<int>& faces, const std::vector<int>& order, int dir, int row_index);
  // Bind-off (§7.5): runs of loops with nothing above, chained in pass A's
  // direction; the last loop of each chain stays on its needle.
  void bind_off_row(const std::vector<int>& order, int dir);
  // Chain bind-off of tops[i..j] (consecutive needles). When a live loop
  // sits next to the run, the chain runs towards it and its last loop is
  // moved onto it, so the next stitch there holds the chain and nothing can
  // unravel; otherwise the last loop stays on its needle.
  void bind_off(const std::vector<int>& tops, std::size_t i, std::size_t j, int dir);

  const StitchMesh& mesh_;
  const Schedule& s_;
  const EmitParams& params_;
  const int shift_;
  EmittedPiece result_;
  int line_ = 0;
  int racking_ = 0;
  bool in_ = false;
  bool hook_pending_ = false;
  bool stitched_ = false;
  int carrier_at_ = 0;      // needle of the last loop made (the yarn hangs from it)
  char carrier_bed_ = 'f';  // and its bed
  PassKey pass_{};
  int lo_ = 0, hi_ = 0, last_ = kNoNeedle;
  int min_needle_ = kNoNeedle, max_needle_ = -kNoNeedle;
  std::map<int, std::vector<int>> front_, back_;
  std::map<int, int> where_;              // course edge -> front needle of its loop
  std::map<int, std::vector<int>> uses_;  // needle -> rows (indices in the piece) that need it
  int row_index_ = 0;
  std::set<int> row_needles_;            // needles the current row moves loops from or to, or knits
  std::map<int, std::size_t> arriving_;  // the current row's work needles -> loops arriving
  std::set<int> stay_;              // the current row's empty work needles with room for one tail
  std::map<int, int> destination_;  // the current row's source needles -> their loops' work needle
};

}  // namespace planner
