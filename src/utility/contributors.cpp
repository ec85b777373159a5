#include "fvx/utility/utility.hpp"

#include "fvx/core/error.hpp"

namespace fvx::utility {

Contributors::List& Contributors::make(std::size_t cell) {
  std::uint32_t& slot = slot_[cell];
  std::vector<List>& lists = lists_[stripe(cell)];
  if (slot == 0) {
    FVX_ASSERT(lists.size() < UINT32_MAX, "Contributors: more lists than a slot can name");
    lists.push_back(kNone);
    slot = std::uint32_t(lists.size());
  }
  return lists[slot - 1];
}

bool Contributors::operator==(const Contributors& other) const {
  if (size() != other.size()) return false;
  for (std::size_t cell = 0; cell < size(); ++cell)
    if ((*this)[cell] != other[cell]) return false;
  return true;
}

}  // namespace fvx::utility
