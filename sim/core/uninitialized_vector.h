#pragma once
// A vector whose resize leaves new elements of a trivial type as they come (default-initialised), for
// large buffers that a parallel loop fills completely right after. std::vector's resize would zero
// them first on the calling thread: a serial pass over memory touched for the first time, page faults
// and all, before the threads write it again.

#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

namespace pp5 {

template <class T, class Base = std::allocator<T>>
class DefaultInitAllocator : public Base {
    using Traits = std::allocator_traits<Base>;

public:
    template <class U>
    struct rebind {
        using other = DefaultInitAllocator<U, typename Traits::template rebind_alloc<U>>;
    };

    using Base::Base;

    // Without arguments: default-initialise (no zeroing for trivial types).
    template <class U>
    void construct(U* where) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(where)) U;
    }
    template <class U, class... Args>
    void construct(U* where, Args&&... args) {
        Traits::construct(static_cast<Base&>(*this), where, std::forward<Args>(args)...);
    }
};

// Every element must be written before it is read.
template <class T>
using UninitializedVector = std::vector<T, DefaultInitAllocator<T>>;

}  // namespace pp5
