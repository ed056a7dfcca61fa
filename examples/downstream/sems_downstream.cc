// SPDX-License-Identifier: GPL-3.0-or-later
/* A downstream program built against an installed gr-sems (see CMakeLists.txt beside it):
 * streams random-scene frames through pilot_mapper -> target_channel -> pilot_extractor
 * on the bundle's mask, then classifies them with the bundle's decoder.
 *
 *   sems_downstream <bundle dir> [frames]
 * Prints "sems_downstream: frames=F accuracy=A" and exits non-zero on any error.
 */
#include <gnuradio/blocks/vector_sink.h>
#include <gnuradio/blocks/vector_source.h>
#include <gnuradio/sems/blocks/pilot_extractor.h>
#include <gnuradio/sems/blocks/pilot_mapper.h>
#include <gnuradio/sems/blocks/target_channel.h>
#include <gnuradio/sems/core/common/tags.h>
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <gnuradio/top_block.h>
#include <pmt/pmt.h>
#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

int main(int argc, char** argv)
{
    if (argc < 2) {
        std::fprintf(stderr, "usage: sems_downstream <bundle dir> [frames]\n");
        return 2;
    }
    try {
        namespace sems = gr::sems;
        const std::string dir = argv[1];
        const int frames = argc > 2 ? std::stoi(argv[2]) : 200;
        const auto bundle = sems::model_bundle::load(dir);
        const std::string mask = dir + "/mask.json";
        const auto& fs = bundle.frame;
        const int np = bundle.mask.size();

        auto tb = gr::make_top_block("sems_downstream");
        std::vector<gr_complex> data(size_t(frames) * (fs.grid_size() - np), gr_complex(1.0f, 0.0f));
        auto src = gr::blocks::vector_source_c::make(data);
        auto mapper = sems::pilot_mapper::make(mask);
        auto channel = sems::target_channel::make("", {}, 1, 1, true, "approaching", 0, 0.0, 20.0, 7);
        auto extractor = sems::pilot_extractor::make(mask);
        auto sink = gr::blocks::vector_sink_c::make(np);
        tb->connect(src, 0, mapper, 0);
        tb->connect(mapper, 0, channel, 0);
        tb->connect(channel, 0, extractor, 0);
        tb->connect(extractor, 0, sink, 0);
        tb->run();

        const auto& obs = sink->data();
        const int got = static_cast<int>(obs.size()) / np;
        if (got != frames) {
            std::fprintf(stderr, "sems_downstream: %d frames in, %d out\n", frames, got);
            return 1;
        }
        // Truth from the channel's sems_truth tags, carried by the extractor.
        std::vector<int> truth(frames, -1);
        for (const auto& t : sink->tags())
            if (pmt::eq(t.key, pmt::intern(sems::keys::truth_tag)))
                truth.at(t.offset) =
                    static_cast<int>(pmt::to_long(pmt::dict_ref(t.value, pmt::intern(sems::keys::class_id), pmt::PMT_NIL)));

        sems::bundle_decoder decoder(bundle, 1);
        const auto probs = decoder.classify(obs.data(), frames);
        const int c = static_cast<int>(probs.size()) / frames;
        int correct = 0;
        for (int f = 0; f < frames; ++f) {
            const auto* p = probs.data() + size_t(f) * c;
            correct += int(std::max_element(p, p + c) - p) == truth[f];
        }
        std::printf("sems_downstream: frames=%d accuracy=%.3f\n", frames, double(correct) / frames);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sems_downstream: %s\n", e.what());
        return 1;
    }
}
