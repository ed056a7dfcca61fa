// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: RBF SVM (libsvm) on standardised features. See feature_svm.h. */
#include "core/common/checks.h"
#include <gnuradio/sems/baselines/feature_svm.h>
#include <libsvm/svm.h>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

namespace {
void quiet(const char*) {} // libsvm prints its optimisation log to stdout otherwise
} // namespace

struct feature_svm::impl {
    int d = 0;
    std::vector<double> mean, scale;
    // libsvm's model points into the training nodes: they live as long as the model.
    std::vector<std::vector<svm_node>> nodes;
    std::vector<svm_node*> rows;
    std::vector<double> y;
    svm_problem prob{};
    svm_parameter param{};
    svm_model* model = nullptr;

    ~impl()
    {
        if (model)
            svm_free_and_destroy_model(&model);
    }

    std::vector<svm_node> encode(const std::vector<double>& x) const
    {
        std::vector<svm_node> n(d + 1);
        for (int i = 0; i < d; ++i)
            n[i] = { i + 1, (x[i] - mean[i]) / scale[i] };
        n[d] = { -1, 0.0 };
        return n;
    }
};

feature_svm::feature_svm(const std::vector<std::vector<double>>& features, const std::vector<int>& labels)
    : feature_svm(features, labels, settings{})
{
}

feature_svm::feature_svm(const std::vector<std::vector<double>>& features,
                         const std::vector<int>& labels,
                         settings s)
    : d_impl(new impl)
{
    const std::string who = "feature SVM";
    if (features.empty())
        throw std::invalid_argument(who + ": no training samples");
    if (features.size() != labels.size())
        throw std::invalid_argument(who + ": " + std::to_string(features.size()) + " feature rows but " +
                                    std::to_string(labels.size()) + " labels");
    if (!checks::positive(s.c))
        throw std::invalid_argument(who + ": C must be finite and > 0");
    if (!checks::finite(s.gamma))
        throw std::invalid_argument(who + ": gamma must be finite");
    if (!(s.cache_mb > 0.0))
        throw std::invalid_argument(who + ": cache_mb must be > 0");
    auto& m = *d_impl;
    m.d = static_cast<int>(features[0].size());
    if (m.d < 1)
        throw std::invalid_argument(who + ": feature rows are empty");
    std::set<int> classes;
    for (size_t i = 0; i < features.size(); ++i) {
        if (static_cast<int>(features[i].size()) != m.d)
            throw std::invalid_argument(who + ": row " + std::to_string(i) + " has " +
                                        std::to_string(features[i].size()) + " features, expected " +
                                        std::to_string(m.d));
        for (double v : features[i])
            if (!checks::finite(v))
                throw std::invalid_argument(who + ": row " + std::to_string(i) + " has a non-finite feature");
        if (labels[i] < 0)
            throw std::invalid_argument(who + ": label " + std::to_string(labels[i]) + " is negative");
        classes.insert(labels[i]);
    }
    if (classes.size() < 2)
        throw std::invalid_argument(who + ": training needs at least two classes");

    // z-score per feature; a constant feature keeps scale 1.
    const double n = static_cast<double>(features.size());
    m.mean.assign(m.d, 0.0);
    m.scale.assign(m.d, 0.0);
    for (const auto& x : features)
        for (int i = 0; i < m.d; ++i)
            m.mean[i] += x[i] / n;
    for (const auto& x : features)
        for (int i = 0; i < m.d; ++i)
            m.scale[i] += (x[i] - m.mean[i]) * (x[i] - m.mean[i]) / n;
    for (auto& v : m.scale)
        v = v > 0.0 ? std::sqrt(v) : 1.0;

    for (size_t i = 0; i < features.size(); ++i) {
        m.nodes.push_back(m.encode(features[i]));
        m.y.push_back(labels[i]);
    }
    for (auto& r : m.nodes)
        m.rows.push_back(r.data());
    m.prob.l = static_cast<int>(m.nodes.size());
    m.prob.y = m.y.data();
    m.prob.x = m.rows.data();

    m.param.svm_type = C_SVC;
    m.param.kernel_type = RBF;
    m.param.gamma = s.gamma > 0.0 ? s.gamma : 1.0 / m.d;
    m.param.C = s.c;
    m.param.cache_size = s.cache_mb;
    m.param.eps = 1e-3;
    m.param.shrinking = 1;
    m.param.probability = 0;
    m.param.nr_weight = 0;
    if (const char* err = svm_check_parameter(&m.prob, &m.param))
        throw std::invalid_argument(who + ": libsvm: " + err);
    svm_set_print_string_function(&quiet);
    m.model = svm_train(&m.prob, &m.param);
}

feature_svm::~feature_svm() = default;
feature_svm::feature_svm(feature_svm&&) noexcept = default;

int feature_svm::predict(const std::vector<double>& x) const
{
    if (static_cast<int>(x.size()) != d_impl->d)
        throw std::invalid_argument("feature SVM: got " + std::to_string(x.size()) + " features, expected " +
                                    std::to_string(d_impl->d));
    for (double v : x)
        if (!checks::finite(v))
            throw std::invalid_argument("feature SVM: non-finite feature");
    const auto n = d_impl->encode(x);
    return static_cast<int>(std::lround(svm_predict(d_impl->model, n.data())));
}

int feature_svm::n_features() const { return d_impl->d; }
int feature_svm::n_support_vectors() const { return svm_get_nr_sv(d_impl->model); }

} // namespace sems
} // namespace gr
