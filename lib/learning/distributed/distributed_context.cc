// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: distributed training settings and the trainer's Gloo process group
 * (see lib/learning/distributed/distributed_context.h). */
#include "learning/distributed/distributed_context.h"
#include <cerrno>
#include <chrono>
#include <sstream>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>

#ifdef SEMS_HAVE_GLOO
#include <torch/csrc/distributed/c10d/FileStore.hpp>
#include <torch/csrc/distributed/c10d/ProcessGroupGloo.hpp>
#include <torch/csrc/distributed/c10d/TCPStore.hpp>
#endif

namespace gr {
namespace sems {

namespace {
void bad_setting(const std::string& what) { throw std::invalid_argument("distributed settings: " + what); }

// A whole-string integer from an environment variable; nullopt when unset or empty.
bool env_int(const char* name, long& out)
{
    const char* v = std::getenv(name);
    if (!v || !*v)
        return false;
    char* end = nullptr;
    errno = 0;
    out = std::strtol(v, &end, 10);
    if (errno || *end != '\0')
        bad_setting(std::string("environment variable ") + name + ": expected an integer, got \"" + v + "\"");
    return true;
}
std::string env_string(const char* name)
{
    const char* v = std::getenv(name);
    return v ? v : "";
}
} // namespace

distributed_settings distributed_settings::from_environment()
{
    distributed_settings s;
    long v = 0;
    if (env_int("WORLD_SIZE", v)) {
        if (v < 1)
            bad_setting("environment variable WORLD_SIZE must be >= 1, got " + std::to_string(v));
        s.world_size = static_cast<int>(v);
    }
    if (env_int("RANK", v))
        s.rank = static_cast<int>(v);
    else if (s.world_size > 1)
        bad_setting("WORLD_SIZE is " + std::to_string(s.world_size) + " but RANK is not set");
    s.master_addr = env_string("MASTER_ADDR");
    if (env_int("MASTER_PORT", v)) {
        if (v < 1 || v > 65535)
            bad_setting("environment variable MASTER_PORT must be in [1, 65535], got " + std::to_string(v));
        s.master_port = static_cast<int>(v);
    }
    s.interface = env_string("GLOO_SOCKET_IFNAME");
    s.agent_store = env_string("TORCHELASTIC_USE_AGENT_STORE") == "True"; // torchrun
    return s;
}

void distributed_settings::validate() const
{
    if (world_size < 1)
        bad_setting("world size must be >= 1, got " + std::to_string(world_size));
    if (rank < 0 || rank >= world_size)
        bad_setting("rank must be in [0, world size " + std::to_string(world_size) + "), got " +
                    std::to_string(rank));
    if (master_port < 1 || master_port > 65535)
        bad_setting("master port must be in [1, 65535], got " + std::to_string(master_port));
    if (!(timeout_s > 0.0) || !std::isfinite(timeout_s))
        bad_setting("timeout must be a positive number of seconds");
    if (world_size > 1 && store_file.empty() && master_addr.empty())
        bad_setting("world size " + std::to_string(world_size) +
                    " needs a rendezvous: a store file (--store-file, one machine) or rank 0's address "
                    "(--master-addr or MASTER_ADDR)");
}

bool distributed_settings::available()
{
#ifdef SEMS_HAVE_GLOO
    return true;
#else
    return false;
#endif
}

namespace training {

namespace {
using clock_type = std::chrono::steady_clock;

uint64_t splitmix64(uint64_t x)
{
    x += 0x9E3779B97F4A7C15ULL;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
    return x ^ (x >> 31);
}

[[maybe_unused]] bool is_loopback(const std::string& host) // unused without Gloo
{
    return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
}
} // namespace

#ifdef SEMS_HAVE_GLOO
struct distributed_context::impl {
    c10::intrusive_ptr<c10d::Store> store;
    c10::intrusive_ptr<c10d::ProcessGroupGloo> pg;
    std::chrono::milliseconds timeout;
    std::string who; // "rank r of W"

    [[noreturn]] void fail(const std::string& op, const std::string& why) const
    {
        std::ostringstream os;
        os << "distributed training (" << who << "): " << op << " failed: " << why
           << " -- another rank died, could not connect or stopped answering (timeout " << timeout.count() / 1000.0
           << " s)";
        throw std::runtime_error(os.str());
    }
    // Gloo's errors (c10::Error, std::runtime_error) become fail(): one message naming the rank.
    template <class F>
    auto guarded(const std::string& op, F&& f) -> decltype(f())
    {
        try {
            return f();
        } catch (const c10::Error& e) {
            fail(op, e.what_without_backtrace());
        } catch (const std::runtime_error& e) {
            if (std::string(e.what()).rfind("distributed training (", 0) == 0)
                throw;
            fail(op, e.what());
        } catch (const std::exception& e) {
            fail(op, e.what());
        }
    }
    void wait(const std::string& op, const c10::intrusive_ptr<c10d::Work>& work)
    {
        guarded(op, [&] {
            // Gloo's own timeout (the context's) fires first; this one is the backstop.
            if (!work->wait(timeout + std::chrono::seconds(5)))
                fail(op, "no answer");
        });
    }
    template <class F>
    void run(const std::string& op, F&& start)
    {
        wait(op, guarded(op, std::forward<F>(start)));
    }
    void all_reduce(torch::Tensor& t, c10d::ReduceOp op, const std::string& what)
    {
        std::vector<torch::Tensor> v{ t };
        c10d::AllreduceOptions o;
        o.reduceOp = op;
        run(what, [&] { return pg->allreduce(v, o); });
    }

    // The gradient all-reduce in flight between start_gradient_all_reduce() and
    // finish_gradient_all_reduce(): the bucket and where its slices go back.
    struct pending_gradients {
        c10::intrusive_ptr<c10d::Work> work;
        torch::Tensor bucket;
        std::vector<torch::Tensor> params, buffers;
    };
    std::unique_ptr<pending_gradients> pending;
};
#else
struct distributed_context::impl {
};
#endif

distributed_context::distributed_context(const distributed_settings& s) : d_s(s)
{
    d_s.validate();
    if (!active())
        return;
#ifndef SEMS_HAVE_GLOO
    throw std::runtime_error(
        "distributed training (world size " + std::to_string(d_s.world_size) +
        ") is not available: gr-sems's learning library was built without Gloo (libgloo-dev was not found "
        "when CMake configured it). Install libgloo-dev (scripts/install_deps.sh) and re-run cmake.");
#else
    d_impl = std::make_unique<impl>();
    auto& m = *d_impl;
    m.timeout = std::chrono::milliseconds(static_cast<int64_t>(std::ceil(d_s.timeout_s * 1000.0)));
    m.who = "rank " + std::to_string(d_s.rank) + " of " + std::to_string(d_s.world_size);
    const std::string where = d_s.store_file.empty()
                                  ? "TCPStore " + d_s.master_addr + ":" + std::to_string(d_s.master_port)
                                  : "FileStore " + d_s.store_file;
    try {
        if (!d_s.store_file.empty()) {
            auto fs = c10::make_intrusive<c10d::FileStore>(d_s.store_file, d_s.world_size);
            fs->setTimeout(m.timeout);
            m.store = fs;
        } else {
            c10d::TCPStoreOptions o;
            o.port = static_cast<std::uint16_t>(d_s.master_port);
            o.isServer = d_s.rank == 0 && !d_s.agent_store;
            o.numWorkers = static_cast<std::size_t>(d_s.world_size);
            o.waitWorkers = true;
            o.timeout = m.timeout;
            m.store = c10::make_intrusive<c10d::TCPStore>(d_s.master_addr, o);
        }
        auto opts = c10d::ProcessGroupGloo::Options::create(m.timeout);
        // Gloo's pairs: the given interface; loopback when every rank is on this machine.
        if (!d_s.interface.empty())
            opts->devices.push_back(c10d::ProcessGroupGloo::createDeviceForInterface(d_s.interface));
        else if (!d_s.store_file.empty() || is_loopback(d_s.master_addr))
            opts->devices.push_back(c10d::ProcessGroupGloo::createDeviceForHostname("127.0.0.1"));
        else
            opts->devices.push_back(c10d::ProcessGroupGloo::createDefaultDevice());
        opts->threads = 1; // one collective at a time
        m.pg = c10::make_intrusive<c10d::ProcessGroupGloo>(m.store, d_s.rank, d_s.world_size, opts);
    } catch (const c10::Error& e) {
        m.fail("rendezvous at " + where, e.what_without_backtrace());
    } catch (const std::exception& e) {
        m.fail("rendezvous at " + where, e.what());
    }
#endif
}

distributed_context::~distributed_context() = default;

uint64_t distributed_context::rank_seed(uint64_t seed) const
{
    return d_s.rank == 0 ? seed : splitmix64(seed ^ splitmix64(static_cast<uint64_t>(d_s.rank)));
}

int64_t distributed_context::share(int64_t total) const
{
    const int64_t w = d_s.world_size;
    return total / w + (d_s.rank < total % w ? 1 : 0);
}

#ifdef SEMS_HAVE_GLOO

void distributed_context::broadcast_module(torch::nn::Module& mod)
{
    if (!active())
        return;
    torch::NoGradGuard ng;
    std::vector<torch::Tensor> all;
    for (auto& p : mod.parameters())
        all.push_back(p.detach());
    for (auto& b : mod.buffers())
        all.push_back(b.detach());
    for (auto& t : all) {
        if (!t.is_contiguous())
            throw std::logic_error("broadcast_module: non-contiguous tensor");
        std::vector<torch::Tensor> v{ t };
        c10d::BroadcastOptions o;
        o.rootRank = 0;
        d_impl->run("broadcast of the initial weights", [&] { return d_impl->pg->broadcast(v, o); });
    }
}

void distributed_context::all_reduce_gradients(const torch::optim::Optimizer& opt,
                                               const std::vector<std::shared_ptr<torch::nn::Module>>& modules)
{
    start_gradient_all_reduce(opt, modules);
    finish_gradient_all_reduce();
}

void distributed_context::start_gradient_all_reduce(const torch::optim::Optimizer& opt,
                                                    const std::vector<std::shared_ptr<torch::nn::Module>>& modules)
{
    if (!active())
        return;
    if (d_impl->pending)
        throw std::logic_error("start_gradient_all_reduce: the previous one was not finished");
    const auto t0 = clock_type::now();
    torch::NoGradGuard ng;
    auto p = std::make_unique<impl::pending_gradients>();
    for (const auto& g : opt.param_groups())
        for (const auto& t : g.params())
            p->params.push_back(t);
    for (const auto& m : modules)
        for (auto& b : m->buffers())
            if (b.is_floating_point())
                p->buffers.push_back(b);
    int64_t total = static_cast<int64_t>(p->params.size()); // one "gradient defined" flag per parameter
    for (const auto& t : p->params)
        total += t.numel();
    for (const auto& b : p->buffers)
        total += b.numel();
    p->bucket = torch::empty({ total }, torch::kFloat);
    float* flag = p->bucket.data_ptr<float>();
    int64_t off = static_cast<int64_t>(p->params.size());
    for (size_t i = 0; i < p->params.size(); ++i) {
        const auto& t = p->params[i];
        const int64_t n = t.numel();
        auto slot = p->bucket.slice(0, off, off + n);
        if (t.grad().defined()) {
            slot.copy_(t.grad().reshape({ -1 }));
            flag[i] = 1.0f;
        } else {
            slot.zero_();
            flag[i] = 0.0f;
        }
        off += n;
    }
    for (const auto& b : p->buffers) {
        p->bucket.slice(0, off, off + b.numel()).copy_(b.reshape({ -1 }));
        off += b.numel();
    }
    std::vector<torch::Tensor> v{ p->bucket };
    c10d::AllreduceOptions o;
    o.reduceOp = c10d::ReduceOp::SUM;
    p->work = d_impl->guarded("gradient all-reduce", [&] { return d_impl->pg->allreduce(v, o); });
    d_impl->pending = std::move(p);
    d_grad_seconds += std::chrono::duration<double>(clock_type::now() - t0).count();
    d_grad_floats = total;
}

void distributed_context::finish_gradient_all_reduce()
{
    if (!active())
        return;
    if (!d_impl->pending)
        throw std::logic_error("finish_gradient_all_reduce: no gradient all-reduce was started");
    const auto t0 = clock_type::now();
    torch::NoGradGuard ng;
    const auto p = std::move(d_impl->pending);
    d_impl->wait("gradient all-reduce", p->work);
    p->bucket.div_(static_cast<double>(d_s.world_size));
    const float* flag = p->bucket.data_ptr<float>();
    int64_t off = static_cast<int64_t>(p->params.size());
    for (size_t i = 0; i < p->params.size(); ++i) {
        auto t = p->params[i];
        const int64_t n = t.numel();
        if (flag[i] > 0.0f) { // some rank has this gradient
            if (!t.grad().defined())
                t.mutable_grad() = torch::zeros_like(t);
            t.mutable_grad().copy_(p->bucket.slice(0, off, off + n).view(t.sizes()));
        }
        off += n;
    }
    for (auto& b : p->buffers) {
        b.copy_(p->bucket.slice(0, off, off + b.numel()).view(b.sizes()));
        off += b.numel();
    }
    d_grad_seconds += std::chrono::duration<double>(clock_type::now() - t0).count();
    d_grad_calls += 1;
}

namespace {
std::vector<double> reduce_doubles(distributed_context::impl* m,
                                   std::vector<double> v,
                                   c10d::ReduceOp op,
                                   const std::string& what)
{
    auto t = torch::tensor(v, torch::kDouble);
    m->all_reduce(t, op, what);
    auto a = t.accessor<double, 1>();
    for (size_t i = 0; i < v.size(); ++i)
        v[i] = a[i];
    return v;
}
} // namespace

std::vector<double> distributed_context::all_reduce_sum(std::vector<double> v)
{
    return active() && !v.empty() ? reduce_doubles(d_impl.get(), std::move(v), c10d::ReduceOp::SUM, "metric all-reduce")
                                  : v;
}
std::vector<double> distributed_context::all_reduce_min(std::vector<double> v)
{
    return active() && !v.empty() ? reduce_doubles(d_impl.get(), std::move(v), c10d::ReduceOp::MIN, "all-reduce (min)")
                                  : v;
}
std::vector<double> distributed_context::all_reduce_max(std::vector<double> v)
{
    return active() && !v.empty() ? reduce_doubles(d_impl.get(), std::move(v), c10d::ReduceOp::MAX, "all-reduce (max)")
                                  : v;
}

torch::Tensor distributed_context::all_gather(const torch::Tensor& t)
{
    if (!active())
        return t;
    const int w = d_s.world_size;
    std::vector<double> len(w, 0.0);
    len[d_s.rank] = static_cast<double>(t.numel());
    len = all_reduce_sum(len);
    int64_t longest = 0;
    for (double l : len)
        longest = std::max<int64_t>(longest, static_cast<int64_t>(l));
    auto padded = torch::zeros({ longest }, t.options());
    padded.slice(0, 0, t.numel()).copy_(t.reshape({ -1 }));
    std::vector<std::vector<torch::Tensor>> out(1);
    for (int r = 0; r < w; ++r)
        out[0].push_back(torch::empty({ longest }, t.options()));
    std::vector<torch::Tensor> in{ padded };
    d_impl->run("all-gather", [&] { return d_impl->pg->allgather(out, in); });
    std::vector<torch::Tensor> parts;
    for (int r = 0; r < w; ++r)
        parts.push_back(out[0][r].slice(0, 0, static_cast<int64_t>(len[r])));
    return torch::cat(parts, 0);
}

void distributed_context::check_in_sync(const std::vector<std::shared_ptr<torch::nn::Module>>& modules,
                                        const std::string& what)
{
    if (!active())
        return;
    torch::NoGradGuard ng;
    std::vector<double> fp;
    for (const auto& m : modules)
        for (const auto& p : m->parameters()) {
            auto d = p.detach().to(torch::kDouble);
            fp.push_back(d.sum().item<double>());
            fp.push_back((d * d).sum().item<double>());
        }
    const auto hi = all_reduce_max(fp), lo = all_reduce_min(fp);
    for (size_t i = 0; i < fp.size(); ++i)
        if (hi[i] != lo[i])
            throw std::runtime_error("distributed training (rank " + std::to_string(d_s.rank) +
                                     "): the ranks' parameters differ after " + what + " (checksum " +
                                     std::to_string(i) + ": " + std::to_string(lo[i]) + " .. " +
                                     std::to_string(hi[i]) + "); the ranks must run the same settings");
}

#else // without Gloo: the constructor refuses world size > 1, so these are identities.

void distributed_context::broadcast_module(torch::nn::Module&) {}
void distributed_context::all_reduce_gradients(const torch::optim::Optimizer&,
                                               const std::vector<std::shared_ptr<torch::nn::Module>>&)
{
}
void distributed_context::start_gradient_all_reduce(const torch::optim::Optimizer&,
                                                    const std::vector<std::shared_ptr<torch::nn::Module>>&)
{
}
void distributed_context::finish_gradient_all_reduce() {}
std::vector<double> distributed_context::all_reduce_sum(std::vector<double> v) { return v; }
std::vector<double> distributed_context::all_reduce_min(std::vector<double> v) { return v; }
std::vector<double> distributed_context::all_reduce_max(std::vector<double> v) { return v; }
torch::Tensor distributed_context::all_gather(const torch::Tensor& t) { return t; }
void distributed_context::check_in_sync(const std::vector<std::shared_ptr<torch::nn::Module>>&, const std::string&)
{
}

#endif

} // namespace training
} // namespace sems
} // namespace gr
