// The balancing policies by name, kind and default gain: what --balance
// accepts and what the configuration needs to know of a policy (whether it
// moves boundaries during the frame, its gain). The policies themselves are
// in balance/ (policy.h), each with its maker; a new policy is one file
// there, and its maker's declaration and one entry in policy_table.cpp.
#pragma once
#include <memory>
#include <string>
#include <vector>

namespace rt {

class BalancePolicy;  // balance/policy.h

enum class PolicyKind { None, Static, Dynamic };
struct PolicyInfo {
    const char* name;
    const char* help;
    PolicyKind kind;
    double defaultGain;  // BalanceConfig::gain when not set
    std::unique_ptr<BalancePolicy> (*make)();  // dynamic policies only
};
// Every policy, in the order --help lists them.
const std::vector<PolicyInfo>& policies();
const PolicyInfo* findPolicy(const std::string& name);  // nullptr if unknown

}  // namespace rt
