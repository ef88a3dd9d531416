// Parameters of the modules that Model does not name: each module keeps its compiled parameters
// in a struct of its own, stored here by type (a module adds its files, not a member of Model).
// Value semantics: copying a Model copies every block.
#pragma once

#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

namespace silt {

class ModuleParams {
 public:
  ModuleParams() = default;
  ModuleParams(const ModuleParams& o) { *this = o; }
  ModuleParams& operator=(const ModuleParams& o) {
    if (this == &o) return *this;
    blocks_.clear();
    for (const auto& [key, block] : o.blocks_) blocks_.emplace_back(key, block->clone());
    return *this;
  }
  ModuleParams(ModuleParams&&) = default;
  ModuleParams& operator=(ModuleParams&&) = default;

  // The block of type P, made (value-initialised) if absent.
  template <class P>
  P& get() {
    for (auto& [key, block] : blocks_)
      if (key == tag<P>()) return static_cast<Holder<P>&>(*block).value;
    blocks_.emplace_back(tag<P>(), std::make_unique<Holder<P>>());
    return static_cast<Holder<P>&>(*blocks_.back().second).value;
  }
  // The block of type P; throws when the module did not compile one.
  template <class P>
  const P& get() const {
    for (const auto& [key, block] : blocks_)
      if (key == tag<P>()) return static_cast<const Holder<P>&>(*block).value;
    throw std::logic_error("no parameters of this module in the model");
  }
  template <class P>
  bool has() const {
    for (const auto& [key, block] : blocks_)
      if (key == tag<P>()) return true;
    return false;
  }

 private:
  struct Block {
    virtual ~Block() = default;
    virtual std::unique_ptr<Block> clone() const = 0;
  };
  template <class P>
  struct Holder final : Block {
    P value{};
    std::unique_ptr<Block> clone() const override { return std::make_unique<Holder>(*this); }
  };
  template <class P>
  static const void* tag() {
    static const char k = 0;
    return &k;
  }
  std::vector<std::pair<const void*, std::unique_ptr<Block>>> blocks_;
};

}  // namespace silt
