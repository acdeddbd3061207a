#pragma once
// An owning pointer whose copy is a deep copy: T::clone() where T has it (a polymorphic base
// such as Model), else T's copy constructor. So a class holding one stays copyable by default,
// for checkpoints of whole scenes.
#include <memory>
#include <utility>

namespace incise::sim {

template <class T>
class ClonePtr {
 public:
  ClonePtr() = default;
  ClonePtr(std::unique_ptr<T> p) : p_(std::move(p)) {}  // NOLINT: implicit, like unique_ptr
  ClonePtr(const ClonePtr& other) : p_(copy_of(other.p_.get())) {}
  ClonePtr(ClonePtr&&) noexcept = default;
  ClonePtr& operator=(const ClonePtr& other) {
    if (this != &other) p_ = copy_of(other.p_.get());
    return *this;
  }
  ClonePtr& operator=(ClonePtr&&) noexcept = default;
  ClonePtr& operator=(std::unique_ptr<T> p) {
    p_ = std::move(p);
    return *this;
  }

  void reset() { p_.reset(); }
  T* get() const { return p_.get(); }
  T* operator->() const { return p_.get(); }
  T& operator*() const { return *p_; }
  explicit operator bool() const { return p_ != nullptr; }

 private:
  static std::unique_ptr<T> copy_of(const T* p) {
    if (p == nullptr) return nullptr;
    if constexpr (requires { p->clone(); }) {
      return p->clone();
    } else {
      return std::make_unique<T>(*p);
    }
  }

  std::unique_ptr<T> p_;
};

}  // namespace incise::sim
