// planner::schoolbus: transfer planning between two rows of a flat sheet,
// after the schoolbus algorithm of Lin, Narayanan and McCann, "Efficient
// transfer planning for flat knitting" (2018), as paper §7.5 asks.
//
// Every loop that moves boards the "bus" (the back bed) at racking 0, then
// the bed racks one way step by step (1, 2, ... up to the machine's limit)
// and each loop gets off onto the front bed when the racking equals what it
// still has to travel; then the other way (-1, -2, ...). A loop that has to
// travel further than the racking limit gets off as far as it can (at the
// limit, or nearer when that needle holds a loop or is someone's
// destination) and boards again in the next round. A loop with no such stop
// within reach and at most twice the limit to go boards at a racking
// against its travel, onto a back needle ahead of it that no other loop
// boards, and gets off at its destination in the same round (the yarn to
// its neighbours stretches by up to the racking limit then). Loops that
// share a destination stack there (a decrease). Each loop is transferred
// twice per round, and loops that board at racking 0 keep their spacing on
// the bus, so the yarn between them is never stretched more than by one
// racking step at a time.
//
// Input: moves of front-bed loops (all loops on one needle move together;
// two moves from one needle must share their destination). `occupied(n)`
// says whether front needle n holds a loop that does not move; a loop may
// get off only at its destination when that is occupied (stacking), never
// at an intermediate stop. Throws std::logic_error when no plan exists
// under these rules (no free intermediate stop within reach, and further
// than twice the racking limit to go).
#pragma once

#include <functional>
#include <stdexcept>
#include <vector>

namespace planner {

struct LoopMove {
  int from = 0;  // front needle now
  int to = 0;    // front needle wanted
};

struct Transfer {
  int racking = 0;
  bool to_back = false;  // xfer f front b back (else xfer b back f front)
  int front = 0;
  int back = 0;
};

// Thrown when some loop finds no free needle within reach on its way: the
// held loops around it leave no stop. The stitch mesh, not the program, is
// then at fault (schedule_stitches reports it as S911).
class NoTransferRoute : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

std::vector<Transfer> schoolbus(const std::vector<LoopMove>& moves,
                                const std::function<bool(int)>& occupied, int max_racking = 8);

}  // namespace planner
