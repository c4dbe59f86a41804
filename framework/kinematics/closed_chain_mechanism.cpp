// The closed-chain sizes every build has: planar (3) and spatial (6) parallel mechanisms.

#include "kincal/framework/kinematics/closed_chain_mechanism_impl.hpp"

namespace kincal {

template class ClosedChainMechanism<3>;
template class ClosedChainMechanism<6>;

}  // namespace kincal
