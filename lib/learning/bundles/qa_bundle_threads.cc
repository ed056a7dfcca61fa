// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: two decoders in one process keep their own intra-op thread counts.
 * Before, the constructor set LibTorch's count for the process and the last decoder
 * built won; now each inference sets it in the calling thread (OpenMP: per thread). */
#include "qa/qa_assert.h"
#include "qa/qa_files.h"
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <ATen/Parallel.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

using namespace gr::sems;

namespace {
using gr::sems::qa::models_dir;
} // namespace

class qa_bundle_threads : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_bundle_threads);
    CPPUNIT_TEST(two_decoders_keep_their_threads);
    CPPUNIT_TEST_SUITE_END();

public:
    void two_decoders_keep_their_threads()
    {
        const auto b = model_bundle::load(models_dir() + "classifier");
        // Built in this order, "the last one wins" would give both 2 threads.
        const bundle_decoder one(b, 1), two(b, 2);
        const int batch = 4;
        std::vector<gr_complex> obs(static_cast<size_t>(batch) * one.n_pilots());
        for (size_t i = 0; i < obs.size(); ++i)
            obs[i] = gr_complex(std::cos(0.1f * i), std::sin(0.37f * i));
        const auto ref = one.classify(obs.data(), batch);

        std::atomic<int> wrong_one{ 0 }, wrong_two{ 0 }, differ{ 0 };
        auto run = [&](const bundle_decoder& dec, int want, std::atomic<int>& wrong) {
            for (int i = 0; i < 40; ++i) { // both threads at once, interleaved
                const auto p = dec.classify(obs.data(), batch);
                if (at::get_num_threads() != want)
                    ++wrong;
                for (size_t k = 0; k < p.size(); ++k)
                    if (std::abs(p[k] - ref[k]) > 1e-5f)
                        ++differ;
            }
        };
        std::thread t1(run, std::cref(one), 1, std::ref(wrong_one));
        std::thread t2(run, std::cref(two), 2, std::ref(wrong_two));
        t1.join();
        t2.join();
        CPPUNIT_ASSERT_EQUAL(0, wrong_one.load());
        CPPUNIT_ASSERT_EQUAL(0, wrong_two.load());
        CPPUNIT_ASSERT_EQUAL(0, differ.load()); // same network, same answers, any thread count
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_bundle_threads);
