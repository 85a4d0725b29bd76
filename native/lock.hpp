// The buffer's lock and its waiters' condition, owned by the compiled core (Buffer.lock is this, bound):
// reentrant, as Python's RLock, and a condition that wait_for_transform waits on and every insertion
// notifies. Whoever blocks on it lets go of the GIL first (its holder may need the GIL to let go), and
// waits in slices, checking Python's signals between them, so that Ctrl-C still interrupts a wait.
#pragma once

#include <nanobind/nanobind.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <utility>
#include <thread>

namespace tfpython {

namespace nb = nanobind;

class Lock {
   public:
    using Clock = std::chrono::steady_clock;

    // Taken by this thread (again, if it holds it already). Raises what a signal's handler raised while
    // it waited, not having taken it.
    void acquire() {
        const std::thread::id me = std::this_thread::get_id();
        if (owner_.load(std::memory_order_relaxed) == me) {
            ++count_;
            return;
        }
        if (try_take(me)) {
            count_ = 1;
            return;
        }
        take(me, 1, true);
    }

    void release() {
        if (owner_.load(std::memory_order_relaxed) != std::this_thread::get_id()) {
            throw nb::builtin_exception(nb::exception_type::runtime_error, "cannot release un-acquired lock");
        }
        if (--count_ == 0) let_go();
    }

    // Whether this thread holds it.
    bool owned() const { return owner_.load(std::memory_order_relaxed) == std::this_thread::get_id(); }

    // threading.Condition.wait: let go of it (however many times this thread holds it) until notified or
    // `timeout` seconds have passed, then take it again as held before. Whether it was notified.
    bool wait(double timeout) {
        const std::thread::id me = std::this_thread::get_id();
        const Clock::time_point deadline =
            Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout));
        if (owner_.load(std::memory_order_relaxed) != me) {
            throw nb::builtin_exception(nb::exception_type::runtime_error, "cannot wait on un-acquired lock");
        }
        const int64_t held = std::exchange(count_, 0);
        uint64_t generation = 0;
        {
            const std::lock_guard<std::mutex> guard(mutex_);
            generation = generation_;
        }
        ++waiting_;  // before letting go: whoever takes it next and notifies sees this waiter
        let_go();
        bool notified = false;
        while (true) {
            {
                const nb::gil_scoped_release unlocked;
                std::unique_lock<std::mutex> guard(mutex_);
                notified = changed_.wait_until(guard, std::min(deadline, Clock::now() + SLICE),
                                               [&] { return generation_ != generation; });
            }
            if (notified || Clock::now() >= deadline || PyErr_CheckSignals() != 0) break;
        }
        const bool interrupted = PyErr_Occurred() != nullptr;
        --waiting_;
        take(me, held, false);  // held again before the signal's error leaves, as Condition.wait does
        if (interrupted) throw nb::python_error();
        return notified;
    }

    // Wakes every thread in wait(); costs nothing where none waits.
    void notify_all() {
        if (waiting_.load(std::memory_order_relaxed) == 0) return;
        const std::lock_guard<std::mutex> guard(mutex_);
        ++generation_;
        changed_.notify_all();
    }

   private:
    static constexpr std::chrono::milliseconds SLICE{50};

    // Taken by `me` if free (one atomic instruction: no mutex where no other thread wants it). Sequentially
    // consistent, failing too: a blocked thread's failed try must be ordered against let_go()'s store and its
    // read of `blocked_`, or both could miss each other and the wake-up wait out a SLICE (x86 pays nothing
    // more: a locked cmpxchg either way).
    bool try_take(std::thread::id me) {
        std::thread::id none;
        return owner_.compare_exchange_strong(none, me);
    }

    // Free, a thread blocked in take() woken. Sequentially consistent, as take()'s count of the blocked: either
    // a blocked thread's next try finds it free, or this finds that thread counted and wakes it (under the
    // mutex, so not between its try and its wait).
    void let_go() {
        owner_.store(std::thread::id());
        if (blocked_.load() == 0) return;
        const std::lock_guard<std::mutex> guard(mutex_);
        free_.notify_one();
    }

    // Held `count` times by `me` once free, the GIL let go meanwhile; with `interruptible`, a signal's
    // handler that raises stops the wait (and leaves it not taken).
    void take(std::thread::id me, int64_t count, bool interruptible) {
        ++blocked_;
        struct Unblock {
            std::atomic<int64_t>& blocked;
            ~Unblock() { --blocked; }
        } const unblock{blocked_};
        while (true) {
            {
                const nb::gil_scoped_release unlocked;
                std::unique_lock<std::mutex> guard(mutex_);
                if (free_.wait_for(guard, SLICE, [&] { return try_take(me); })) {
                    count_ = count;
                    return;
                }
            }
            if (interruptible && PyErr_CheckSignals() != 0) throw nb::python_error();
        }
    }

    // The holder (none: free), and how many times it holds it (read and written by the holder only).
    std::atomic<std::thread::id> owner_{};
    int64_t count_ = 0;
    mutable std::mutex mutex_;  // guards generation_, and the waits on the conditions
    std::condition_variable free_, changed_;
    uint64_t generation_ = 0;          // notifications so far
    std::atomic<int64_t> waiting_{0};  // threads in wait()
    std::atomic<int64_t> blocked_{0};  // threads in take()
};

// `lock` held for a scope.
class Locked {
   public:
    explicit Locked(Lock& lock) : lock_(lock) { lock_.acquire(); }
    Locked(const Locked&) = delete;
    Locked& operator=(const Locked&) = delete;
    ~Locked() { lock_.release(); }

   private:
    Lock& lock_;
};

// What a read of the buffer's state that keeps the GIL needs against insertions from other threads:
// nothing under the GIL (each insertion holds it through its one call into the core, and a read that
// lets go of it holds the buffer's lock), the buffer's lock without one (a free-threaded Python).
class ReadLocked {
   public:
#ifdef Py_GIL_DISABLED
    explicit ReadLocked(Lock& lock) : locked_(lock) {}

   private:
    Locked locked_;
#else
    explicit ReadLocked(Lock&) {}
#endif
};

}  // namespace tfpython
