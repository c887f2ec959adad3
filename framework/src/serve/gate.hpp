// The door of `fixpoint serve` (docs/serve-api.md, "Slow clients"): cpp-httplib 0.11.4 gives
// each connection a thread of its pool for as long as the client takes to send its request,
// with a timeout per read that a client sending a byte a second resets for ever; forty such
// clients held the 32 threads and every other request timed out. Here a connection waits for
// its request's head in a waiting room of its own (one thread polls them all), within a
// deadline, and only a whole head takes a request thread; the head and the body must then
// arrive within that same deadline, enforced by the stream httplib reads them through. The
// connections open at once are capped: one more is answered 503 at once.
#pragma once

#include <httplib.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace fp::host::serve_detail {

struct GateLimits {
    /// From the first byte of a request to the last of its body; also the most a response
    /// may take to be written. FIXPOINT_SERVE_DEADLINE_MS overrides it (for the tests).
    std::chrono::milliseconds deadline{15000};
    /// Connections open at once (waiting for their head or being served).
    /// FIXPOINT_SERVE_CONNECTIONS overrides it (for the tests).
    std::size_t connections = 256;
    /// Requests reading a body that had not arrived whole with their head: each holds a
    /// request thread until its body is in (or the deadline), so fewer than the threads.
    std::size_t bodies = 16;
    /// Request threads: long polls hold one each for up to 10 s.
    std::size_t threads = 32;

    /// The defaults, with the environment's overrides (an unreadable value is ignored).
    static GateLimits from_environment();
};

class Room;

/// An httplib::Server whose connections pass the gate: it takes over what httplib does with
/// an accepted socket (process_and_close_socket), and runs httplib's own request parsing and
/// routing (process_request) on its request threads, over a stream with the deadline.
class GatedServer : public httplib::Server {
public:
    explicit GatedServer(GateLimits limits);
    ~GatedServer() override;
    GatedServer(const GatedServer&) = delete;
    GatedServer& operator=(const GatedServer&) = delete;

    /// After stop() and the listener's end: the waiting room closes its connections, the
    /// reads in flight fail within 0.1 s (a write goes out if the socket takes it at once), and
    /// the request threads end.
    void close_gate();

    /// In the pre-routing handler, once the request is admitted: whether its body may be
    /// read (it is already here, or one of the `bodies` slots is free). False: answer 503.
    static bool may_read_body(const httplib::Request& req);
    /// In a handler: the body is read; the response is written within the deadline from
    /// now (the handler itself, a render or a long poll, has no deadline).
    static void handler_starts();
    static void handler_ends();

    const GateLimits& limits() const { return limits_; }

private:
    friend class Room;
    bool process_and_close_socket(socket_t sock) override;
    /// One request of a connection whose head is here, on a request thread.
    void serve_one(socket_t sock, std::string in, std::chrono::steady_clock::time_point deadline,
                   unsigned served);

    GateLimits limits_;
    std::unique_ptr<Room> room_;
    std::unique_ptr<httplib::ThreadPool> workers_;
    std::atomic<bool> closing_{false};
    std::atomic<std::size_t> open_{0};
    std::atomic<std::size_t> bodies_{0};
    std::once_flag closed_;
};

} // namespace fp::host::serve_detail
