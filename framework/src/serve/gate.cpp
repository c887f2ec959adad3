#include "gate.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <utility>

namespace fp::host::serve_detail {

using Clock = std::chrono::steady_clock;

namespace {

// The most a head may hold (httplib itself takes lines of up to 8 KiB, of a few headers each).
constexpr std::size_t max_head = 64u << 10;
// How often a wait looks whether the server is stopping.
constexpr std::chrono::milliseconds stop_poll{100};

int ms_until(Clock::time_point t, Clock::time_point now) {
    if (t <= now) return 0;
    // Rounded up, so that a wait does not wake just before its deadline and spin.
    return int(std::chrono::ceil<std::chrono::milliseconds>(t - now).count());
}

void close_connection(socket_t sock) {
    ::shutdown(sock, SHUT_RDWR);
    ::close(sock);
}

// An answer written by the gate itself (no request thread): one send into the socket's empty
// buffer, then the connection closed. What the client had sent is read away first where it
// is already here, so that the close does not reset the connection before it reads this.
void refuse(socket_t sock, int status, const char* reason, const std::string& message) {
    const std::string body = "{\"error\":\"" + message + "\"}";
    const std::string head =
        "HTTP/1.1 " + std::to_string(status) + " " + reason +
        "\r\nContent-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) +
        "\r\nConnection: close\r\n\r\n";
    const std::string all = head + body;
    (void)::send(sock, all.data(), all.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
    ::shutdown(sock, SHUT_WR);
    char sink[4096];
    for (int i = 0; i < 16 && ::recv(sock, sink, sizeof sink, MSG_DONTWAIT) > 0; ++i) {
    }
    ::close(sock);
}

// Whether `in` holds a whole head (its empty line), looking from where `before` bytes ended.
bool has_head(const std::string& in, std::size_t before) {
    return in.find("\r\n\r\n", before >= 3 ? before - 3 : 0) != std::string::npos;
}

std::size_t env_number(const char* name, std::size_t fallback) {
    const char* v = std::getenv(name);
    if (!v || !*v) return fallback;
    char* end = nullptr;
    const unsigned long long n = std::strtoull(v, &end, 10);
    return *end == '\0' && n > 0 ? std::size_t(n) : fallback;
}

// httplib's listener hands each accepted socket to its task queue: this one runs the task on
// the listener's thread, for the gate only files the socket (or refuses it) and returns.
class InlineQueue final : public httplib::TaskQueue {
public:
    void enqueue(std::function<void()> fn) override { fn(); }
    void shutdown() override {}
};

// The stream httplib reads a request from and writes its response to: first the bytes the
// waiting room read, then the socket, every wait bounded by the per-read timeout and by the
// connection's deadline (a trickle resets the former, never the latter).
class GateStream final : public httplib::Stream {
public:
    GateStream(socket_t sock, std::string in, Clock::time_point deadline, const std::atomic<bool>& closing,
               std::chrono::milliseconds timeout)
        : sock_(sock), in_(std::move(in)), deadline_(deadline), closing_(closing), timeout_(timeout) {}

    bool is_readable() const override { return off_ < in_.size() || wait(POLLIN); }
    bool is_writable() const override { return wait(POLLOUT); }

    ssize_t read(char* ptr, size_t size) override {
        if (off_ >= in_.size()) {
            in_.clear();
            off_ = 0;
            char buf[4096];
            for (;;) {
                if (!wait(POLLIN)) return -1;
                const ssize_t n = ::recv(sock_, buf, sizeof buf, MSG_DONTWAIT);
                if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) continue;
                if (n <= 0) return n;
                in_.assign(buf, std::size_t(n));
                break;
            }
        }
        const std::size_t n = std::min(size, in_.size() - off_);
        std::memcpy(ptr, in_.data() + off_, n);
        off_ += n;
        return ssize_t(n);
    }

    // Whole or not at all (Stream::write_format counts on it).
    ssize_t write(const char* ptr, size_t size) override {
        std::size_t done = 0;
        while (done < size) {
            if (!wait(POLLOUT)) return -1;
            const ssize_t n = ::send(sock_, ptr + done, size - done, MSG_DONTWAIT | MSG_NOSIGNAL);
            if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) continue;
            if (n < 0) return -1;
            done += std::size_t(n);
        }
        return ssize_t(size);
    }

    void get_remote_ip_and_port(std::string& ip, int& port) const override {
        address(::getpeername, ip, port);
    }
    void get_local_ip_and_port(std::string& ip, int& port) const override {
        address(::getsockname, ip, port);
    }
    socket_t socket() const override { return sock_; }

    /// The bytes read and not yet taken: how much of a body came with its head, and what a
    /// client sent after its request (its next one, on a kept connection).
    std::size_t buffered() const { return in_.size() - off_; }
    std::string unread() const { return in_.substr(off_); }
    void set_deadline(Clock::time_point t) { deadline_ = t; }
    void no_deadline() { deadline_ = Clock::time_point::max(); }

    bool holds_body_slot = false;

private:
    // Ready within the per-read (or per-write) timeout and before the deadline; polled in
    // steps, so that a stopping server is noticed. Once it stops, reads end, and a write goes
    // out only if the socket takes it at once: the answer of a handler that ends as the server
    // stops (a render's "the server is stopping") still reaches its client, and a client that
    // reads nothing cannot hold the stop.
    bool wait(short events) const {
        const Clock::time_point now = Clock::now();
        const Clock::time_point end = std::min(deadline_, now + timeout_);
        for (;;) {
            if (closing_.load()) {
                pollfd p{sock_, events, 0};
                return events == POLLOUT && ::poll(&p, 1, 0) > 0;
            }
            const Clock::time_point t = Clock::now();
            if (t >= end) return false;
            pollfd p{sock_, events, 0};
            const int r = ::poll(&p, 1, std::min(ms_until(end, t), int(stop_poll.count())));
            if (r < 0 && errno == EINTR) continue;
            if (r < 0) return false;
            if (r > 0) return true;
        }
    }

    template <class F>
    void address(F get, std::string& ip, int& port) const {
        sockaddr_storage a{};
        socklen_t len = sizeof a;
        ip.clear();
        port = 0;
        if (get(sock_, reinterpret_cast<sockaddr*>(&a), &len) != 0) return;
        char host[NI_MAXHOST], serv[NI_MAXSERV];
        if (::getnameinfo(reinterpret_cast<sockaddr*>(&a), len, host, sizeof host, serv, sizeof serv,
                          NI_NUMERICHOST | NI_NUMERICSERV) != 0)
            return;
        ip = host;
        port = std::atoi(serv);
    }

    socket_t sock_;
    std::string in_;
    std::size_t off_ = 0;
    Clock::time_point deadline_;
    const std::atomic<bool>& closing_;
    std::chrono::milliseconds timeout_;
};

// The request being served on this thread (serve_one), for the hooks the handlers call.
thread_local GateStream* t_stream = nullptr;
thread_local std::atomic<std::size_t>* t_bodies = nullptr;
thread_local const GateLimits* t_limits = nullptr;

void release_body_slot() {
    if (t_stream && t_stream->holds_body_slot) {
        t_stream->holds_body_slot = false;
        t_bodies->fetch_sub(1);
    }
}

} // namespace

GateLimits GateLimits::from_environment() {
    GateLimits l;
    l.deadline =
        std::chrono::milliseconds(env_number("FIXPOINT_SERVE_DEADLINE_MS", std::size_t(l.deadline.count())));
    l.connections = env_number("FIXPOINT_SERVE_CONNECTIONS", l.connections);
    return l;
}

// ---------------------------------------------------------------- the waiting room
// Connections waiting for the head of a request: new ones (the deadline runs from the
// accept) and kept ones (waiting at most httplib's keep-alive time for their next request's
// first byte, then the deadline runs from it). One thread polls them all.
class Room {
public:
    explicit Room(GatedServer& s) : s_(s) {
        if (::pipe2(wake_, O_CLOEXEC | O_NONBLOCK) != 0)
            throw std::system_error(errno, std::generic_category());
        thread_ = std::thread([this] { run(); });
    }
    ~Room() {
        stop();
        ::close(wake_[0]);
        ::close(wake_[1]);
    }
    Room(const Room&) = delete;
    Room& operator=(const Room&) = delete;

    /// Files a connection; false when the room is closed (the caller closes it).
    bool add(socket_t sock, std::string in, unsigned served) {
        const Clock::time_point now = Clock::now();
        const bool idle = in.empty() && served > 0;
        Waiting w{sock, std::move(in),
                  idle ? now + std::chrono::seconds(s_.keep_alive_timeout_sec_) : now + s_.limits_.deadline,
                  idle, served};
        {
            std::lock_guard<std::mutex> l(m_);
            if (stopped_) return false;
            arriving_.push_back(std::move(w));
        }
        const char b = 1;
        (void)!::write(wake_[1], &b, 1);
        return true;
    }

    void stop() {
        {
            std::lock_guard<std::mutex> l(m_);
            if (stopped_) return;
            stopped_ = true;
        }
        const char b = 1;
        (void)!::write(wake_[1], &b, 1);
        thread_.join();
    }

private:
    struct Waiting {
        socket_t sock;
        std::string in;
        Clock::time_point deadline;
        bool idle;
        unsigned served;
    };

    void drop(Waiting& w) {
        close_connection(w.sock);
        s_.open_.fetch_sub(1);
    }

    void dispatch(Waiting& w) {
        s_.workers_->enqueue([&s = s_, sock = w.sock, in = std::move(w.in), d = w.deadline,
                              n = w.served]() mutable { s.serve_one(sock, std::move(in), d, n); });
    }

    void run() {
        std::vector<Waiting> waiting;
        std::vector<pollfd> fds;
        for (;;) {
            {
                std::lock_guard<std::mutex> l(m_);
                if (stopped_) break;
                for (Waiting& w : arriving_) {
                    // A kept connection may hold its next request already.
                    if (has_head(w.in, 0))
                        dispatch(w);
                    else
                        waiting.push_back(std::move(w));
                }
                arriving_.clear();
            }
            const Clock::time_point now = Clock::now();
            int timeout = int(stop_poll.count()) * 10;
            for (std::size_t i = 0; i < waiting.size();) {
                Waiting& w = waiting[i];
                if (now >= w.deadline) {
                    if (w.idle) {
                        drop(w);
                    } else {
                        refuse(w.sock, 408, "Request Timeout",
                               "the request did not arrive within " +
                                   std::to_string(s_.limits_.deadline.count()) + " ms");
                        s_.open_.fetch_sub(1);
                    }
                    waiting[i] = std::move(waiting.back());
                    waiting.pop_back();
                    continue;
                }
                timeout = std::min(timeout, ms_until(w.deadline, now));
                ++i;
            }
            fds.assign(1, pollfd{wake_[0], POLLIN, 0});
            for (const Waiting& w : waiting) fds.push_back(pollfd{w.sock, POLLIN, 0});
            if (::poll(fds.data(), fds.size(), timeout) < 0 && errno != EINTR) continue;
            char sink[64];
            while (::read(wake_[0], sink, sizeof sink) > 0) {
            }
            // Backwards, so that removing one (the last moved into its place) skips none.
            for (std::size_t i = waiting.size(); i-- > 0;) {
                if (!(fds[i + 1].revents & (POLLIN | POLLHUP | POLLERR))) continue;
                if (!take(waiting[i])) {
                    waiting[i] = std::move(waiting.back());
                    waiting.pop_back();
                }
            }
        }
        for (Waiting& w : waiting) drop(w);
        std::lock_guard<std::mutex> l(m_);
        for (Waiting& w : arriving_) drop(w);
        arriving_.clear();
    }

    // Reads what `w` sent; false when it left the room (dispatched, refused or closed).
    bool take(Waiting& w) {
        char buf[4096];
        const ssize_t n = ::recv(w.sock, buf, sizeof buf, MSG_DONTWAIT);
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return true;
        if (n <= 0) {
            drop(w);
            return false;
        }
        if (w.idle) {
            w.idle = false;
            w.deadline = Clock::now() + s_.limits_.deadline;
        }
        const std::size_t before = w.in.size();
        w.in.append(buf, std::size_t(n));
        if (has_head(w.in, before)) {
            dispatch(w);
            return false;
        }
        if (w.in.size() > max_head) {
            refuse(w.sock, 431, "Request Header Fields Too Large",
                   "the request's head is longer than " + std::to_string(max_head) + " bytes");
            s_.open_.fetch_sub(1);
            return false;
        }
        return true;
    }

    GatedServer& s_;
    int wake_[2] = {-1, -1};
    std::mutex m_;
    bool stopped_ = false;
    std::vector<Waiting> arriving_;
    std::thread thread_;
};

// ---------------------------------------------------------------- the server
GatedServer::GatedServer(GateLimits limits)
    : limits_(limits), workers_(std::make_unique<httplib::ThreadPool>(limits.threads)) {
    new_task_queue = [] { return new InlineQueue; };
    room_ = std::make_unique<Room>(*this);
}

GatedServer::~GatedServer() { close_gate(); }

void GatedServer::close_gate() {
    std::call_once(closed_, [this] {
        closing_.store(true);
        room_->stop();
        workers_->shutdown();
    });
}

// On the listener's thread, for each accepted socket: filed in the waiting room, or refused
// at once when the connections open are at the cap (or the server is stopping).
bool GatedServer::process_and_close_socket(socket_t sock) {
    if (closing_.load()) {
        refuse(sock, 503, "Service Unavailable", "the server is stopping");
        return false;
    }
    if (open_.fetch_add(1) >= limits_.connections) {
        open_.fetch_sub(1);
        refuse(sock, 503, "Service Unavailable",
               "the server has " + std::to_string(limits_.connections) + " connections open: try again");
        return false;
    }
    if (!room_->add(sock, {}, 0)) {
        close_connection(sock);
        open_.fetch_sub(1);
        return false;
    }
    return true;
}

void GatedServer::serve_one(socket_t sock, std::string in, Clock::time_point deadline, unsigned served) {
    const auto timeout = std::chrono::milliseconds(read_timeout_sec_ * 1000 + read_timeout_usec_ / 1000);
    GateStream strm(sock, std::move(in), deadline, closing_, timeout);
    t_stream = &strm;
    t_bodies = &bodies_;
    t_limits = &limits_;
    const bool last = closing_.load() || served + 1 >= keep_alive_max_count_;
    bool closed = false;
    bool ok = false;
    try {
        ok = process_request(strm, last, closed, nullptr);
    } catch (...) {
        ok = false; // (httplib catches the handlers' exceptions; this is its own failing)
    }
    release_body_slot();
    t_stream = nullptr;
    if (ok && !closed && !last && room_->add(sock, strm.unread(), served + 1)) return;
    close_connection(sock);
    open_.fetch_sub(1);
}

bool GatedServer::may_read_body(const httplib::Request& req) {
    if (!t_stream) return true;
    const std::string length = req.get_header_value("Content-Length");
    const unsigned long long n = std::strtoull(length.c_str(), nullptr, 10);
    if (n <= t_stream->buffered()) return true; // here already: read without waiting
    if (t_bodies->fetch_add(1) >= t_limits->bodies) {
        t_bodies->fetch_sub(1);
        return false;
    }
    t_stream->holds_body_slot = true;
    return true;
}

void GatedServer::handler_starts() {
    release_body_slot();
    if (t_stream) t_stream->no_deadline();
}

void GatedServer::handler_ends() {
    if (t_stream) t_stream->set_deadline(Clock::now() + t_limits->deadline);
}

} // namespace fp::host::serve_detail
