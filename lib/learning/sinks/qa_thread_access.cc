// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: every setter and getter of every C++ block, called from another thread while
 * flowgraphs stream (the Python/GRC case):
 *   frequency domain: mapper -> channel -> extractors -> both sinks, and -> range_doppler_map
 *   time domain:      mapper -> inverse FFT -> target_channel_td -> frame_sync, and with the
 *                     transmitted stream -> leakage_canceller -> cfo_corrector;
 *                     phase_noise_source -> head
 *   an array:         mapper -> 8-element channel -> extractor -> position sink, range-angle map
 * Under ThreadSanitizer (scripts/sanitize_thread.sh) this is the race test; in the normal
 * and ASan builds it checks that the streams still end with every frame accounted for. */
#include "qa/qa_assert.h"
#include <gnuradio/blocks/head.h>
#include <gnuradio/blocks/null_sink.h>
#include <gnuradio/blocks/null_source.h>
#include <gnuradio/blocks/vector_to_stream.h>
#include <gnuradio/fft/fft_v.h>
#include <gnuradio/sems/blocks/cfo_corrector.h>
#include <gnuradio/sems/blocks/frame_sync.h>
#include <gnuradio/sems/blocks/leakage_canceller.h>
#include <gnuradio/sems/blocks/phase_noise_source.h>
#include <gnuradio/sems/blocks/pilot_extractor.h>
#include <gnuradio/sems/blocks/pilot_mapper.h>
#include <gnuradio/sems/blocks/range_angle_map.h>
#include <gnuradio/sems/blocks/range_doppler_map.h>
#include <gnuradio/sems/blocks/target_channel.h>
#include <gnuradio/sems/blocks/target_channel_td.h>
#include <gnuradio/sems/learning/sinks/classifier_sink.h>
#include <gnuradio/sems/learning/sinks/delay_estimator_sink.h>
#include <gnuradio/sems/learning/sinks/position_sink.h>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <gnuradio/top_block.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <numeric>
#include <thread>

using namespace gr::sems;

class qa_thread_access : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_thread_access);
    CPPUNIT_TEST(setters_and_getters_while_streaming);
    CPPUNIT_TEST_SUITE_END();

public:
    void setters_and_getters_while_streaming()
    {
        const char* src = std::getenv("SEMS_SOURCE_DIR");
        const std::string models = std::string(src ? src : ".") + "/models/";
        const auto cls = model_bundle::load(models + "classifier");
        const auto dly = model_bundle::load(models + "delay_single");
        const auto fs = cls.frame;
        const uint64_t n_frames = 300;
        std::vector<int> all(static_cast<size_t>(fs.grid_size()));
        std::iota(all.begin(), all.end(), 0);

        auto mapper = pilot_mapper::make("", all, fs.n_symbols, fs.n_subcarriers);
        auto head = gr::blocks::head::make(sizeof(gr_complex) * fs.n_subcarriers, n_frames * fs.n_symbols);
        auto channel = target_channel::make("", {}, 1, 1, true, "approaching", 0, 0.0, 10.0, 3, fs.n_symbols, fs.n_subcarriers);
        auto ex_c = pilot_extractor::make(models + "classifier/mask.json", {}, fs.n_symbols, fs.n_subcarriers);
        auto ex_d = pilot_extractor::make(models + "delay_single/mask.json", {}, fs.n_symbols, fs.n_subcarriers);
        auto sink_c = classifier_sink::make(cls.directory, cls.mask.size(), 8, 1, 16, fs.n_symbols, fs.n_subcarriers);
        auto sink_d = delay_estimator_sink::make(dly.directory, dly.mask.size(), 8, 1, 16, fs.n_symbols,
                                                 fs.n_subcarriers);
        auto rdm = range_doppler_map::make(models + "classifier/mask.json", {}, fs.n_symbols, fs.n_subcarriers);
        auto tb = gr::make_top_block("thread_access");
        tb->connect(mapper, 0, head, 0);
        tb->connect(head, 0, channel, 0);
        tb->connect(channel, 0, ex_c, 0);
        tb->connect(channel, 0, ex_d, 0);
        tb->connect(ex_c, 0, sink_c, 0);
        tb->connect(ex_d, 0, sink_d, 0);
        tb->connect(ex_c, 0, rdm, 0);
        tb->connect(rdm, 0, gr::blocks::null_sink::make(sizeof(float) * fs.n_symbols * fs.n_subcarriers), 0);

        // The time-domain chain as ofdm_tx builds it (unitary inverse FFT), without a
        // cyclic prefix; the delay bundle's mask (pilots over 31 subcarriers, so frame_sync locks).
        const uint64_t n_frames_td = 40;
        const int m = fs.n_subcarriers;
        auto mapper_td = pilot_mapper::make(models + "delay_single/mask.json", {}, fs.n_symbols, m);
        auto head_td = gr::blocks::head::make(sizeof(gr_complex) * m, n_frames_td * fs.n_symbols);
        auto ifft = gr::fft::fft_v<gr_complex, false>::make(m, std::vector<float>(m, 1.0f / std::sqrt(float(m))), false);
        auto serial = gr::blocks::vector_to_stream::make(sizeof(gr_complex), m);
        auto channel_td = target_channel_td::make("", {}, 1, 1, true, 0, 0.0, 20.0, 5, fs.n_symbols, m, fs.bandwidth_hz,
                                                  fs.carrier_hz, fs.symbol_interval_s, 0);
        auto sync = frame_sync::make(models + "delay_single/mask.json", {}, fs.n_symbols, m, gr_complex(1.0f, 0.0f), 1.0, 0);
        auto tb_td = gr::make_top_block("thread_access_td");
        tb_td->connect(gr::blocks::null_source::make(sizeof(gr_complex)), 0, mapper_td, 0); // data symbols
        tb_td->connect(mapper_td, 0, head_td, 0);
        tb_td->connect(head_td, 0, ifft, 0);
        tb_td->connect(ifft, 0, serial, 0);
        tb_td->connect(serial, 0, channel_td, 0);
        tb_td->connect(channel_td, 0, sync, 0);
        tb_td->connect(sync, 0, gr::blocks::null_sink::make(sizeof(gr_complex)), 0);
        // The radio blocks: the received stream less the transmitted one's leakage, then the
        // CFO estimate (the stream's M-sample symbols read as M - 1 samples behind a 1-sample
        // prefix, one frame per window: the windows line up, the estimate is not the point); an
        // oscillator's phase noise.
        const int frame_len = fs.n_symbols * m;
        auto canceller = leakage_canceller::make(4, frame_len, 0.5, true, true, 0.0);
        auto cfo = cfo_corrector::make(m - 1, 1, fs.n_symbols, 0.5, 10.0);
        const uint64_t noise_samples = n_frames_td * frame_len;
        auto noise = phase_noise_source::make(fs.bandwidth_hz, -90.0, 100e3, 1);
        tb_td->connect(channel_td, 0, canceller, 0);
        tb_td->connect(serial, 0, canceller, 1);
        tb_td->connect(canceller, 0, cfo, 0);
        tb_td->connect(cfo, 0, gr::blocks::null_sink::make(sizeof(gr_complex)), 0);
        auto head_noise = gr::blocks::head::make(sizeof(gr_complex), noise_samples);
        tb_td->connect(noise, 0, head_noise, 0);
        tb_td->connect(head_noise, 0, gr::blocks::null_sink::make(sizeof(gr_complex)), 0);

        // An array's chain: an 8-element ULA's streams into one extractor, the position sink and
        // the range-angle map (the position bundle's mask and array).
        const uint64_t n_frames_array = 40;
        const std::string position = models + "position_ula8";
        const std::string ula = models + "arrays/ula8_3g.json";
        auto mapper_a = pilot_mapper::make(position + "/mask.json", {}, fs.n_symbols, m);
        auto head_a = gr::blocks::head::make(sizeof(gr_complex) * m, n_frames_array * fs.n_symbols);
        auto channel_a = target_channel::make(R"({"format": "sems.scene", "version": 1, "array": "ula8_3g",
            "random": {"classes": ["car"], "azimuth_rad": [-0.8, 0.8]}})", {}, 1, 1, true, "approaching", 0, 0.0, 20.0,
                                              7, fs.n_symbols, m, fs.bandwidth_hz, fs.carrier_hz, fs.symbol_interval_s,
                                              "paper", 0, "frame", 0.1, 8);
        auto ex_a = pilot_extractor::make(position + "/mask.json", {}, fs.n_symbols, m, gr_complex(1.0f, 0.0f), 8);
        auto sink_p = position_sink::make(position, 8, ex_a->n_pilots(), 8, 1, 16);
        auto ram = range_angle_map::make(ula, position + "/mask.json", {}, fs.n_symbols, m, fs.carrier_hz, 32);
        auto tb_a = gr::make_top_block("thread_access_array");
        tb_a->connect(gr::blocks::null_source::make(sizeof(gr_complex)), 0, mapper_a, 0);
        tb_a->connect(mapper_a, 0, head_a, 0);
        tb_a->connect(head_a, 0, channel_a, 0);
        for (int k = 0; k < 8; ++k)
            tb_a->connect(channel_a, k, ex_a, k);
        tb_a->connect(ex_a, 0, sink_p, 0);
        tb_a->connect(ex_a, 0, ram, 0);
        tb_a->connect(ram, 0, gr::blocks::null_sink::make(sizeof(float) * 32 * m), 0);

        tb_td->start();
        tb_a->start();
        std::atomic<bool> stop{ false };
        std::atomic<uint64_t> calls{ 0 };
        std::thread poker([&] {
            double sink = 0.0;
            for (int i = 0; !stop; ++i) {
                mapper->set_pilot_power(1.0 + (i % 3));
                mapper->set_data_power(1.0);
                sink += mapper->pilot_power() + mapper->data_power() + mapper->frames() + mapper->n_pilots() +
                        mapper->data_per_frame() + mapper->mask().size();
                channel->set_snr_db(i % 2 ? 10.0 : 20.0);
                sink += channel->snr_db() + channel->frames() + channel->nonfinite_symbols() +
                        channel->settings().n_symbols + channel->scene_json().size();
                for (const auto& ex : { ex_c, ex_d })
                    sink += ex->frames_out() + ex->frames_dropped_partial() + ex->frames_skipped_nonfinite() +
                            ex->n_pilots() + ex->mask().size();
                sink_c->set_metrics_period(i % 5);
                sink_d->set_metrics_period(i % 7);
                sink += sink_c->frames() + sink_c->frames_scored() + sink_c->frames_skipped() +
                        sink_c->frames_faulted() + sink_c->accuracy() + sink_c->confusion().size() +
                        sink_c->class_names().size() + sink_c->batch_size() + sink_c->metrics_period();
                sink += sink_d->frames() + sink_d->frames_scored() + sink_d->frames_skipped() +
                        sink_d->frames_faulted() + sink_d->mae_index() + sink_d->mae_m() + sink_d->batch_size() +
                        sink_d->metrics_period();
                sink += rdm->n_pilots() + rdm->frames_out() + rdm->frames_skipped_nonfinite();
                mapper_td->set_pilot_power(1.0);
                mapper_td->set_data_power(1.0);
                channel_td->set_snr_db(i % 2 ? 20.0 : 30.0);
                sink += mapper_td->frames() + channel_td->snr_db() + channel_td->frames() +
                        channel_td->nonfinite_symbols() + channel_td->misaligned_tags() +
                        channel_td->settings().cp_len + channel_td->scene_json().size();
                sink += sync->locked() + sync->offset() + sync->metric() + sync->failures() + sync->frame_len();
                sink += canceller->taps().size() + canceller->image_taps().size() + std::abs(canceller->dc()) +
                        canceller->windows() + canceller->held() + canceller->stream_error().size();
                sink += cfo->cfo() + cfo->timing() + cfo->windows() + noise->diffusion() + noise->samples();
                channel_a->set_snr_db(i % 2 ? 20.0 : 30.0);
                sink_p->set_metrics_period(i % 3);
                sink += ex_a->frames_out() + ex_a->n_elements() + sink_p->frames() + sink_p->frames_scored() +
                        sink_p->frames_skipped() + sink_p->frames_faulted() + sink_p->mae_index() + sink_p->mae_m() +
                        sink_p->frames_scored_azimuth() + sink_p->rmse_azimuth_rad() + sink_p->batch_size() +
                        sink_p->metrics_period();
                sink += ram->n_elements() + ram->n_pilots() + ram->frames_out() + ram->frames_skipped_nonfinite();
                if (i % 50 == 49) {
                    sink_c->reset_metrics();
                    sink_d->reset_metrics();
                    sink_p->reset_metrics();
                }
                calls++;
                std::this_thread::yield();
            }
            (void)sink;
        });
        tb->run();
        tb_td->wait();
        tb_a->wait();
        stop = true;
        poker.join();
        CPPUNIT_ASSERT(calls > 0);
        // Resets make the sinks' totals partial; the extractors count every frame.
        CPPUNIT_ASSERT_EQUAL(n_frames, ex_c->frames_out());
        CPPUNIT_ASSERT_EQUAL(n_frames, ex_d->frames_out());
        CPPUNIT_ASSERT_EQUAL(sink_c->frames(), sink_c->frames_scored() + sink_c->frames_skipped());
        CPPUNIT_ASSERT_EQUAL(uint64_t(0), sink_c->frames_faulted() + sink_d->frames_faulted());
        CPPUNIT_ASSERT_EQUAL(n_frames, rdm->frames_out());
        CPPUNIT_ASSERT_EQUAL(n_frames_td, channel_td->frames());
        CPPUNIT_ASSERT(sync->locked());
        CPPUNIT_ASSERT_EQUAL(n_frames_array, ex_a->frames_out());
        CPPUNIT_ASSERT_EQUAL(n_frames_array, ram->frames_out());
        CPPUNIT_ASSERT_EQUAL(uint64_t(0), sink_p->frames_faulted());
        CPPUNIT_ASSERT(sync->offset() >= 0);
        CPPUNIT_ASSERT_EQUAL(std::string(), canceller->stream_error());
        CPPUNIT_ASSERT(canceller->windows() > 0);
        CPPUNIT_ASSERT(cfo->windows() > 0);
        CPPUNIT_ASSERT(noise->samples() >= noise_samples); // the source may run ahead of head
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_thread_access);
