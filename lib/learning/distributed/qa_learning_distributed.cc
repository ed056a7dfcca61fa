// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the trainer's process group (lib/learning/distributed/distributed_context.h). Two ranks
 * run as two threads of this process over a FileStore in a temporary directory and
 * Gloo on 127.0.0.1:
 *  - the exact part of data parallelism: with the same data split, the all-reduced
 *    gradient of two half batches equals the full batch's gradient (up to float
 *    summation order) and is bit-identical on both ranks; the broadcast gives rank 0's
 *    weights; batch-norm running statistics are averaged;
 *  - metric sums, min/max and the variable-length gather;
 *  - a rank that never comes fails the rendezvous within the timeout;
 *  - settings and environment errors name the setting or variable. */
#include "learning/networks/classifier_decoder.h"
#include "learning/distributed/distributed_context.h"
#include "qa/qa_assert.h"
#include <gnuradio/sems/learning/training/trainer.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <functional>
#include <thread>
#include <unistd.h>

using namespace gr::sems;
using gr::sems::training::distributed_context;
using gr::sems::qa::assert_error;
namespace fsys = std::filesystem;

namespace {

std::string fresh_store()
{
    static std::atomic<int> counter{ 0 };
    const auto dir = fsys::temp_directory_path() / ("sems_qa_dist_" + std::to_string(::getpid()));
    fsys::create_directories(dir);
    const auto p = dir / ("store_" + std::to_string(counter++));
    fsys::remove(p);
    return p.string();
}

distributed_settings rank_settings(int rank, int world, const std::string& store, double timeout = 30.0)
{
    distributed_settings s;
    s.rank = rank;
    s.world_size = world;
    s.store_file = store;
    s.timeout_s = timeout;
    return s;
}

// Runs body(rank, context) on two threads, one per rank; rethrows the first failure.
void two_ranks(const std::function<void(int, distributed_context&)>& body)
{
    const auto store = fresh_store();
    std::exception_ptr err[2];
    std::vector<std::thread> th;
    for (int r = 0; r < 2; ++r)
        th.emplace_back([&, r] {
            try {
                distributed_context ctx(rank_settings(r, 2, store));
                body(r, ctx);
            } catch (...) {
                err[r] = std::current_exception();
            }
        });
    for (auto& t : th)
        t.join();
    for (auto& e : err)
        if (e)
            std::rethrow_exception(e);
}

struct env_guard {
    std::vector<std::string> names{ "WORLD_SIZE", "RANK", "MASTER_ADDR", "MASTER_PORT", "GLOO_SOCKET_IFNAME",
                                    "TORCHELASTIC_USE_AGENT_STORE" };
    env_guard()
    {
        for (const auto& n : names)
            ::unsetenv(n.c_str());
    }
    ~env_guard()
    {
        for (const auto& n : names)
            ::unsetenv(n.c_str());
    }
};

} // namespace

class qa_learning_distributed : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_learning_distributed);
    CPPUNIT_TEST(settings_errors_name_the_setting);
    CPPUNIT_TEST(environment_is_read_and_checked);
    CPPUNIT_TEST(world_of_one_is_the_identity);
    CPPUNIT_TEST(two_ranks_gradient_equals_full_batch);
    CPPUNIT_TEST(two_ranks_collectives);
    CPPUNIT_TEST(missing_rank_fails_within_timeout);
    CPPUNIT_TEST_SUITE_END();

public:
    void settings_errors_name_the_setting()
    {
        auto bad = [](std::function<void(distributed_settings&)> f) {
            distributed_settings s;
            s.world_size = 2;
            s.store_file = "/tmp/x";
            f(s);
            return [s] { s.validate(); };
        };
        assert_error(bad([](auto& s) { s.rank = 2; }), "rank must be in [0, world size 2)", "got 2");
        assert_error(bad([](auto& s) { s.rank = -1; }), "rank must be in");
        assert_error(bad([](auto& s) { s.world_size = 0; }), "world size must be >= 1");
        assert_error(bad([](auto& s) { s.master_port = 70000; }), "master port", "70000");
        assert_error(bad([](auto& s) { s.timeout_s = 0.0; }), "timeout");
        assert_error(bad([](auto& s) { s.store_file.clear(); }), "needs a rendezvous", "--store-file");
        // The trainer's settings: the global batch splits evenly, every rank gets >= 10 frames.
        training_settings t;
        t.distributed.world_size = 3;
        t.distributed.store_file = "/tmp/x";
        t.batch = 64;
        assert_error([t] { t.validate(); }, "batch 64 (global)", "multiple of the world size 3");
        t.batch = 63;
        t.frames = 29;
        assert_error([t] { t.validate(); }, "frames must give each of the 3 ranks >= 10 frames", "29");
        t.frames = 30;
        t.validate();
        CPPUNIT_ASSERT_EQUAL(21, t.to_json()["batch_per_rank"].get<int>());
        CPPUNIT_ASSERT_EQUAL(3, t.to_json()["world_size"].get<int>());
        distributed_settings alone; // world size 1 needs no rendezvous
        alone.validate();
        CPPUNIT_ASSERT(!alone.enabled());
    }

    void environment_is_read_and_checked()
    {
        env_guard g;
        CPPUNIT_ASSERT_EQUAL(1, distributed_settings::from_environment().world_size);
        ::setenv("WORLD_SIZE", "two", 1);
        assert_error([] { distributed_settings::from_environment(); }, "WORLD_SIZE", "\"two\"");
        ::setenv("WORLD_SIZE", "3", 1);
        assert_error([] { distributed_settings::from_environment(); }, "RANK is not set");
        ::setenv("RANK", "2", 1);
        ::setenv("MASTER_ADDR", "127.0.0.1", 1);
        ::setenv("MASTER_PORT", "0x10", 1);
        assert_error([] { distributed_settings::from_environment(); }, "MASTER_PORT");
        ::setenv("MASTER_PORT", "29611", 1);
        ::setenv("GLOO_SOCKET_IFNAME", "lo", 1);
        CPPUNIT_ASSERT(!distributed_settings::from_environment().agent_store); // rank 0 serves the store
        ::setenv("TORCHELASTIC_USE_AGENT_STORE", "True", 1);
        const auto s = distributed_settings::from_environment();
        CPPUNIT_ASSERT(s.agent_store); // torchrun's agent serves it
        CPPUNIT_ASSERT_EQUAL(3, s.world_size);
        CPPUNIT_ASSERT_EQUAL(2, s.rank);
        CPPUNIT_ASSERT_EQUAL(std::string("127.0.0.1"), s.master_addr);
        CPPUNIT_ASSERT_EQUAL(29611, s.master_port);
        CPPUNIT_ASSERT_EQUAL(std::string("lo"), s.interface);
        s.validate();
    }

    void world_of_one_is_the_identity()
    {
        distributed_context ctx(distributed_settings{});
        CPPUNIT_ASSERT(!ctx.active());
        CPPUNIT_ASSERT_EQUAL(uint64_t(12345), ctx.rank_seed(12345)); // the single-process seed
        CPPUNIT_ASSERT_EQUAL(int64_t(1001), ctx.share(1001));
        const std::vector<double> v{ 0.1, 3.0 };
        CPPUNIT_ASSERT(ctx.all_reduce_sum(v) == v);
        CPPUNIT_ASSERT(ctx.all_reduce_min(v) == v);
        auto t = torch::randn({ 5 });
        CPPUNIT_ASSERT(ctx.all_gather(t).is_same(t));
        torch::manual_seed(3);
        auto lin = torch::nn::Linear(4, 3);
        torch::optim::SGD opt(lin->parameters(), 0.1);
        lin->forward(torch::randn({ 2, 4 })).sum().backward();
        const auto g = lin->weight.grad().clone();
        ctx.all_reduce_gradients(opt, { lin.ptr() });
        CPPUNIT_ASSERT(torch::equal(lin->weight.grad(), g)); // untouched, bit for bit
        CPPUNIT_ASSERT_EQUAL(int64_t(0), ctx.gradient_calls());
        if (!distributed_settings::available()) {
            try {
                distributed_context two(rank_settings(0, 2, "/tmp/unused"));
                CPPUNIT_FAIL("world size 2 without Gloo must throw");
            } catch (const std::runtime_error& e) {
                CPPUNIT_ASSERT(std::string(e.what()).find("libgloo-dev") != std::string::npos);
            }
        }
    }

    void two_ranks_gradient_equals_full_batch()
    {
        if (!distributed_settings::available())
            return;
        // A real task decoder in eval mode (batch norm on running statistics, so every
        // frame's loss is independent of the others: the data-parallel identity is exact).
        const int n = 8, m = 16, np = 12, frames = 32;
        nn::classifier_settings cs;
        cs.n_classes = 3;
        auto make = [&](uint64_t seed) {
            torch::manual_seed(seed);
            auto d = std::make_shared<nn::classifier_decoder_module>(n, m, np, cs);
            d->eval();
            return d;
        };
        std::shared_ptr<nn::classifier_decoder_module> dec[2] = { make(1), make(2) };
        auto ref = make(1); // rank 0's initial weights
        torch::manual_seed(9);
        const auto x = torch::randn({ frames, 2, n, m });
        const auto y = torch::randint(0, 3, { frames }, torch::kLong);
        // A parameter no loss uses: its gradient must stay undefined.
        auto unused = torch::zeros({ 3 }, torch::requires_grad());
        std::vector<torch::Tensor> p0 = dec[0]->parameters(), p1 = dec[1]->parameters();
        p0.push_back(unused);
        p1.push_back(unused.detach().clone().requires_grad_());
        std::unique_ptr<torch::optim::SGD> opt[2] = { std::make_unique<torch::optim::SGD>(p0, 0.1),
                                                      std::make_unique<torch::optim::SGD>(p1, 0.1) };
        // Batch-norm running statistics differ per rank and are averaged in the bucket.
        torch::nn::BatchNorm1d bn[2] = { torch::nn::BatchNorm1d(4), torch::nn::BatchNorm1d(4) };
        for (int r = 0; r < 2; ++r) {
            torch::NoGradGuard ng;
            bn[r]->running_mean.fill_(r + 1.0);
            bn[r]->running_var.fill_(2.0 * (r + 1));
        }
        CPPUNIT_ASSERT(!torch::equal(dec[0]->parameters()[0], dec[1]->parameters()[0]));
        two_ranks([&](int r, distributed_context& ctx) {
            ctx.broadcast_module(*dec[r]);
            auto half = torch::arange(r * frames / 2, (r + 1) * frames / 2, torch::kLong);
            auto out = dec[r]->forward(x.index_select(0, half));
            torch::nn::functional::cross_entropy(out.logits, y.index_select(0, half)).backward();
            ctx.all_reduce_gradients(*opt[r], { dec[r], bn[r].ptr() });
            CPPUNIT_ASSERT_EQUAL(int64_t(1), ctx.gradient_calls());
        });
        torch::nn::functional::cross_entropy(ref->forward(x).logits, y).backward();
        const auto pr = ref->parameters();
        for (size_t i = 0; i < pr.size(); ++i) {
            const auto g0 = p0[i].grad(), g1 = p1[i].grad(), gr = pr[i].grad();
            CPPUNIT_ASSERT(torch::equal(p0[i], pr[i])); // rank 0 kept its start
            CPPUNIT_ASSERT(torch::equal(p1[i], pr[i])); // rank 1 got it
            CPPUNIT_ASSERT(torch::equal(g0, g1));       // both ranks hold the same mean
            const double scale = gr.abs().max().item<double>();
            const double diff = (g0 - gr).abs().max().item<double>();
            CPPUNIT_ASSERT_MESSAGE("parameter " + std::to_string(i) + ": |g(B/2+B/2) - g(B)| = " +
                                       std::to_string(diff) + " of " + std::to_string(scale),
                                   diff <= 1e-5 * scale + 1e-9);
        }
        CPPUNIT_ASSERT(!p0.back().grad().defined() && !p1.back().grad().defined());
        for (int r = 0; r < 2; ++r) {
            CPPUNIT_ASSERT(torch::allclose(bn[r]->running_mean, torch::full({ 4 }, 1.5)));
            CPPUNIT_ASSERT(torch::allclose(bn[r]->running_var, torch::full({ 4 }, 3.0)));
        }
    }

    void two_ranks_collectives()
    {
        if (!distributed_settings::available())
            return;
        torch::manual_seed(4);
        torch::nn::Linear lin[2] = { torch::nn::Linear(3, 2), torch::nn::Linear(3, 2) };
        two_ranks([&](int r, distributed_context& ctx) {
            CPPUNIT_ASSERT(ctx.active());
            CPPUNIT_ASSERT_EQUAL(r, ctx.rank());
            CPPUNIT_ASSERT_EQUAL(int64_t(r == 0 ? 501 : 500), ctx.share(1001));
            CPPUNIT_ASSERT_EQUAL(r == 0, ctx.rank_seed(77) == 77);
            const auto sum = ctx.all_reduce_sum({ r + 1.0, 0.25 });
            CPPUNIT_ASSERT(sum == std::vector<double>({ 3.0, 0.5 }));
            CPPUNIT_ASSERT(ctx.all_reduce_min({ r + 1.0 }) == std::vector<double>{ 1.0 });
            CPPUNIT_ASSERT(ctx.all_reduce_max({ r + 1.0 }) == std::vector<double>{ 2.0 });
            // Lengths 3 and 1, concatenated in rank order.
            auto mine = r == 0 ? torch::tensor({ 1.0f, 2.0f, 3.0f }) : torch::tensor({ 4.0f });
            CPPUNIT_ASSERT(torch::equal(ctx.all_gather(mine), torch::tensor({ 1.0f, 2.0f, 3.0f, 4.0f })));
            // Different weights are caught; after the broadcast they agree.
            bool threw = false;
            try {
                ctx.check_in_sync({ lin[r].ptr() }, "test");
            } catch (const std::runtime_error& e) {
                threw = std::string(e.what()).find("parameters differ after test") != std::string::npos;
            }
            CPPUNIT_ASSERT(threw);
            ctx.broadcast_module(*lin[r]);
            ctx.check_in_sync({ lin[r].ptr() }, "broadcast");
        });
    }

    void missing_rank_fails_within_timeout()
    {
        if (!distributed_settings::available())
            return;
        const double timeout = 1.5;
        const auto t0 = std::chrono::steady_clock::now();
        std::string what;
        try {
            distributed_context ctx(rank_settings(0, 2, fresh_store(), timeout));
        } catch (const std::runtime_error& e) {
            what = e.what();
        }
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        CPPUNIT_ASSERT_MESSAGE("no error: " + what, what.find("rank 0 of 2") != std::string::npos);
        CPPUNIT_ASSERT_MESSAGE(what, what.find("rendezvous at FileStore") != std::string::npos);
        CPPUNIT_ASSERT_MESSAGE(what, what.find("timeout 1.5 s") != std::string::npos);
        CPPUNIT_ASSERT_MESSAGE("took " + std::to_string(s) + " s", s >= timeout && s < timeout + 5.0);
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_learning_distributed);
