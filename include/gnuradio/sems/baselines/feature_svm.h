// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: an RBF support-vector classifier on feature vectors (libsvm), with the
 * z-score standardisation learned from the training set. Used by the feature-SVM
 * recognition baseline (doppler_features → feature_svm).
 */
#ifndef INCLUDED_SEMS_BASELINES_FEATURE_SVM_H
#define INCLUDED_SEMS_BASELINES_FEATURE_SVM_H

#include <gnuradio/sems/baselines/api.h>
#include <memory>
#include <vector>

namespace gr {
namespace sems {

class SEMS_BASELINES_API feature_svm
{
public:
    struct settings {
        double c = 10.0;     // soft-margin cost C, > 0
        double gamma = -1.0; // RBF width; <= 0 means 1 / n_features (on standardised features)
        double cache_mb = 100.0;
    };

    // features: n_samples rows of equal length, finite; labels: >= 0, at least two classes.
    // Throws std::invalid_argument naming the problem.
    feature_svm(const std::vector<std::vector<double>>& features, const std::vector<int>& labels, settings s);
    feature_svm(const std::vector<std::vector<double>>& features, const std::vector<int>& labels);
    ~feature_svm();
    feature_svm(feature_svm&&) noexcept;

    int predict(const std::vector<double>& x) const;
    int n_features() const;
    int n_support_vectors() const;

private:
    struct impl;
    std::unique_ptr<impl> d_impl;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BASELINES_FEATURE_SVM_H */
