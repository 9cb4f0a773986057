#pragma once
// The spread of one figure over the ranks of a run (the weak-scaling benches under mpirun): the smallest,
// the largest and the mean, the same on every rank. Collective.
#include "core/comm/communicator.hpp"
#include "core/comm/exact_sum.hpp"

namespace debris {

struct Spread {
  double min, max, mean;
};

inline Spread over_ranks(double v) {
  double mn = v, mx = v;
  comm::allreduce_min(&mn, 1);
  comm::allreduce_max(&mx, 1);
  comm::ExactSum s;
  s.add(v);
  comm::allreduce(&s, 1);
  return {mn, mx, s.value() / comm::size()};
}

}  // namespace debris
