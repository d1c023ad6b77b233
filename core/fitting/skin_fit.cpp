#include "core/fitting/skin_fit.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <bit>
#include <numeric>

namespace softtouch {

namespace {

/// The rotation R minimising Σ |a_i − R b_i|² given H = Σ b_i a_iᵀ (Kabsch; a reflection is turned
/// into the nearest rotation).
Mat3 procrustes(const Mat3& h) {
    const Eigen::JacobiSVD<Mat3> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Mat3 d = Mat3::Identity();
    d(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
    return svd.matrixV() * d * svd.matrixU().transpose();
}

/// Rigid transform of the rest points of `members` onto their positions at `frame` (unweighted).
BoneTransform fitRigid(std::span<const Vec3f> rest, const std::vector<Vec3f>& frame, const std::vector<std::size_t>& members) {
    BoneTransform t;
    if (members.empty())
        return t;
    Vec3 p = Vec3::Zero(), q = Vec3::Zero();
    for (std::size_t i : members) {
        p += rest[i].cast<double>();
        q += frame[i].cast<double>();
    }
    p /= double(members.size());
    q /= double(members.size());
    Mat3 h = Mat3::Zero();
    for (std::size_t i : members)
        h += (rest[i].cast<double>() - p) * (frame[i].cast<double>() - q).transpose();
    t.rotation = members.size() >= 3 ? procrustes(h) : Mat3::Identity();
    t.translation = q - t.rotation * p;
    return t;
}

/// A small deterministic generator (splitmix64) for the seeding.
struct Random {
    std::uint64_t state = 0x5eed;
    std::uint64_t next() {
        std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }
};

/// Error of vertex i following bone j alone over the clip.
double singleBoneError(const SkinFit& skin, std::span<const Vec3f> rest, const std::vector<std::vector<Vec3f>>& frames,
                       std::size_t i, std::size_t j) {
    double e = 0.0;
    const Vec3 p = rest[i].cast<double>();
    for (std::size_t f = 0; f < frames.size(); ++f) {
        const BoneTransform& t = skin.transforms[f][j];
        e += (t.rotation * p + t.translation - frames[f][i].cast<double>()).squaredNorm();
    }
    return e;
}

/// The `count` bones that carry vertex i best alone, best first.
std::vector<std::size_t> bestSingleBones(const SkinFit& skin, std::span<const Vec3f> rest,
                                         const std::vector<std::vector<Vec3f>>& frames, std::size_t i, std::size_t count) {
    const std::size_t k = std::size_t(skin.bones);
    std::vector<std::pair<double, std::size_t>> ranked(k);
    for (std::size_t j = 0; j < k; ++j)
        ranked[j] = {singleBoneError(skin, rest, frames, i, j), j};
    const std::size_t m = std::min(count, k);
    std::partial_sort(ranked.begin(), ranked.begin() + std::ptrdiff_t(m), ranked.end());
    std::vector<std::size_t> best(m);
    for (std::size_t a = 0; a < m; ++a)
        best[a] = ranked[a].second;
    return best;
}

/// Most bones a vertex's weights are chosen among (subsets of at most four of them are tried).
constexpr std::size_t kMostCandidates = 6;

/// Vertex i's weights: among every subset of at most four of `candidates` (at most kMostCandidates), the
/// least-squares weights with Σw = 1 (a KKT system), kept when all are ≥ 0; the best such wins. With
/// `keepCurrent`, the vertex's present weights (whose bones must be among the candidates) stay unless a subset
/// does strictly better, so the step never raises the error.
void solveVertexWeights(SkinFit& skin, std::span<const Vec3f> rest, const std::vector<std::vector<Vec3f>>& frames,
                        std::size_t i, const std::vector<std::size_t>& candidates, bool keepCurrent) {
    using Gram = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMostCandidates, kMostCandidates>;
    using Column = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMostCandidates, 1>;
    const std::size_t m = std::min(candidates.size(), kMostCandidates);
    // Normal equations over the candidates: G = AᵀA, g = Aᵀb, c = bᵀb (A's columns: each bone's transform of
    // the rest point over the frames; b: the clip's positions).
    Gram g = Gram::Zero(Eigen::Index(m), Eigen::Index(m));
    Column gb = Column::Zero(Eigen::Index(m));
    double bb = 0.0;
    const Vec3 p = rest[i].cast<double>();
    for (std::size_t f = 0; f < frames.size(); ++f) {
        Vec3 columns[kMostCandidates];
        for (std::size_t a = 0; a < m; ++a) {
            const BoneTransform& t = skin.transforms[f][candidates[a]];
            columns[a] = t.rotation * p + t.translation;
        }
        const Vec3 b = frames[f][i].cast<double>();
        bb += b.squaredNorm();
        for (std::size_t a = 0; a < m; ++a) {
            gb[Eigen::Index(a)] += columns[a].dot(b);
            for (std::size_t c = 0; c < m; ++c)
                g(Eigen::Index(a), Eigen::Index(c)) += columns[a].dot(columns[c]);
        }
    }
    auto errorOf = [&](const Column& w) { return w.dot(g * w) - 2.0 * w.dot(gb) + bb; };
    double bestError = std::numeric_limits<double>::infinity();
    Column best = Column::Zero(Eigen::Index(m));
    if (keepCurrent) {
        for (std::size_t s = 0; s < 4; ++s) {
            const float w = skin.weights[i][s];
            if (w == 0.0f)
                continue;
            const auto at = std::find(candidates.begin(), candidates.begin() + std::ptrdiff_t(m), skin.joints[i][s]);
            best[at - candidates.begin()] += double(w);
        }
        bestError = errorOf(best);
    }
    for (unsigned subset = 1; subset < (1u << m); ++subset) {
        if (std::popcount(subset) > 4)
            continue;
        std::vector<std::size_t> s;
        for (std::size_t a = 0; a < m; ++a)
            if (subset & (1u << a))
                s.push_back(a);
        const Eigen::Index size = Eigen::Index(s.size());
        Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(size + 1, size + 1);
        Eigen::VectorXd rhs(size + 1);
        for (Eigen::Index a = 0; a < size; ++a) {
            for (Eigen::Index c = 0; c < size; ++c)
                kkt(a, c) = g(Eigen::Index(s[std::size_t(a)]), Eigen::Index(s[std::size_t(c)]));
            kkt(a, size) = kkt(size, a) = 1.0;
            rhs[a] = gb[Eigen::Index(s[std::size_t(a)])];
        }
        rhs[size] = 1.0;
        const Eigen::VectorXd solution = kkt.fullPivLu().solve(rhs);
        Column w = Column::Zero(Eigen::Index(m));
        bool feasible = solution.allFinite();
        for (Eigen::Index a = 0; a < size && feasible; ++a) {
            w[Eigen::Index(s[std::size_t(a)])] = solution[a];
            feasible = solution[a] >= -1e-12;
        }
        if (!feasible)
            continue;
        if (const double e = errorOf(w); e < bestError) {
            bestError = e;
            best = w;
        }
    }
    // The (at most four) bones with weight, heaviest first; unused slots repeat the first at weight 0.
    std::vector<std::pair<double, std::size_t>> used;
    for (std::size_t a = 0; a < m; ++a)
        if (best[Eigen::Index(a)] > 0.0)
            used.push_back({best[Eigen::Index(a)], candidates[a]});
    if (used.empty())
        used.push_back({1.0, candidates.front()});
    std::sort(used.begin(), used.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
    used.resize(std::min<std::size_t>(used.size(), 4));
    double sum = 0.0;
    for (const auto& u : used)
        sum += u.first;
    for (std::size_t s = 0; s < 4; ++s) {
        skin.joints[i][s] = std::uint16_t(s < used.size() ? used[s].second : used.front().second);
        skin.weights[i][s] = s < used.size() ? float(used[s].first / sum) : 0.0f;
    }
}

/// Transforms: per frame and bone from `firstFree` on, with the other bones held, the weighted Procrustes fit
///   minimise Σ_i |q_i − w_i (R p_i + T)|²,  q_i = v_i − Σ_{other bones} w_ik (R_k p_i + T_k)
///   T = q* − R p*,  p* = Σ w² p / Σ w²,  q* = Σ w q / Σ w²,  R from H = Σ w (p − p*) (q − w q*)ᵀ.
/// A bone no vertex weighs keeps its transform.
void updateBoneTransforms(SkinFit& skin, std::span<const Vec3f> rest, const std::vector<std::vector<Vec3f>>& frames,
                          std::size_t firstFree) {
    const std::size_t n = rest.size(), k = std::size_t(skin.bones);
    std::vector<std::vector<std::pair<std::size_t, float>>> influenced(k);  // bone -> (vertex, weight)
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t a = 0; a < 4; ++a)
            if (skin.weights[i][a] > 0.0f)
                influenced[skin.joints[i][a]].push_back({i, skin.weights[i][a]});
    for (std::size_t f = 0; f < frames.size(); ++f) {
        std::vector<Vec3> residual(n);  // v_i − the skin's position: the other bones' part is added back per bone
        for (std::size_t i = 0; i < n; ++i)
            residual[i] = frames[f][i].cast<double>() - skinnedPosition(skin, rest, f, i);
        for (std::size_t j = firstFree; j < k; ++j) {
            if (influenced[j].empty())
                continue;
            BoneTransform& t = skin.transforms[f][j];
            double w2 = 0.0;
            Vec3 pStar = Vec3::Zero(), qStar = Vec3::Zero();
            for (const auto& [i, wf] : influenced[j]) {
                const double w = wf;
                const Vec3 p = rest[i].cast<double>();
                const Vec3 q = residual[i] + w * (t.rotation * p + t.translation);  // this bone's target
                pStar += w * w * p;
                qStar += w * q;
                w2 += w * w;
            }
            pStar /= w2;
            qStar /= w2;
            Mat3 h = Mat3::Zero();
            for (const auto& [i, wf] : influenced[j]) {
                const double w = wf;
                const Vec3 p = rest[i].cast<double>();
                const Vec3 q = residual[i] + w * (t.rotation * p + t.translation);
                h += (w * (p - pStar)) * (q - w * qStar).transpose();
            }
            const BoneTransform old = t;
            t.rotation = procrustes(h);
            t.translation = qStar - t.rotation * pStar;
            for (const auto& [i, wf] : influenced[j]) {  // keep the residuals current for the next bone
                const Vec3 p = rest[i].cast<double>();
                residual[i] -= double(wf) * ((t.rotation * p + t.translation) - (old.rotation * p + old.translation));
            }
        }
    }
}

}  // namespace

Vec3 skinnedPosition(const SkinFit& skin, std::span<const Vec3f> rest, std::size_t frame, std::size_t i) {
    Vec3 x = Vec3::Zero();
    const Vec3 p = rest[i].cast<double>();
    for (int s = 0; s < 4; ++s) {
        const float w = skin.weights[i][std::size_t(s)];
        if (w != 0.0f) {
            const BoneTransform& t = skin.transforms[frame][skin.joints[i][std::size_t(s)]];
            x += double(w) * (t.rotation * p + t.translation);
        }
    }
    return x;
}

SkinFit fitRigidSkin(std::span<const Vec3f> rest, const std::vector<std::vector<Vec3f>>& frames, int bones, int iterations) {
    SkinFit skin;
    const std::size_t n = rest.size(), fcount = frames.size();
    const std::size_t k = std::size_t(std::clamp(bones, 1, int(std::min<std::size_t>(n, 65535))));
    skin.bones = int(k);
    if (n == 0 || fcount == 0)
        return skin;

    // 1. Seeds: k-means (k-means++ seeding) on the vertices' trajectories, so that vertices that move
    //    alike share a bone; then each cluster's rigid motion per frame.
    auto distance2 = [&](std::size_t a, std::size_t b) {
        double d = (rest[a] - rest[b]).cast<double>().squaredNorm();
        for (const auto& frame : frames)
            d += (frame[a] - frame[b]).cast<double>().squaredNorm();
        return d;
    };
    Random random;
    std::vector<std::size_t> centres = {std::size_t(random.next() % n)};
    std::vector<double> nearest(n, std::numeric_limits<double>::infinity());
    while (centres.size() < k) {
        double total = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            nearest[i] = std::min(nearest[i], distance2(i, centres.back()));
            total += nearest[i];
        }
        double pick = random.uniform() * total;
        std::size_t chosen = n - 1;
        for (std::size_t i = 0; i < n; ++i)
            if ((pick -= nearest[i]) <= 0.0) {
                chosen = i;
                break;
            }
        centres.push_back(chosen);
    }
    std::vector<std::size_t> label(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t c = 0; c < k; ++c)
            if (const double d = distance2(i, centres[c]); d < best) {
                best = d;
                label[i] = c;
            }
    }
    skin.transforms.assign(fcount, std::vector<BoneTransform>(k));
    auto fitClusters = [&] {
        std::vector<std::vector<std::size_t>> members(k);
        for (std::size_t i = 0; i < n; ++i)
            members[label[i]].push_back(i);
        for (std::size_t f = 0; f < fcount; ++f)
            for (std::size_t c = 0; c < k; ++c)
                skin.transforms[f][c] = fitRigid(rest, frames[f], members[c]);
    };
    // A few rounds of rigid clustering (each vertex to the bone that carries it best), as Le & Deng seed.
    for (int round = 0; round < 4; ++round) {
        fitClusters();
        std::vector<std::size_t> count(k, 0);
        std::vector<double> errors(n);
        for (std::size_t i = 0; i < n; ++i) {
            double best = std::numeric_limits<double>::infinity();
            for (std::size_t j = 0; j < k; ++j)
                if (const double e = singleBoneError(skin, rest, frames, i, j); e < best) {
                    best = e;
                    label[i] = j;
                }
            errors[i] = best;
            ++count[label[i]];
        }
        // A bone no vertex chose is moved to the worst-fitted vertex.
        for (std::size_t j = 0; j < k; ++j)
            if (count[j] == 0) {
                const std::size_t worst = std::size_t(std::max_element(errors.begin(), errors.end()) - errors.begin());
                label[worst] = j;
                errors[worst] = 0.0;
            }
    }
    fitClusters();
    skin.joints.assign(n, {0, 0, 0, 0});
    skin.weights.assign(n, {1.0f, 0.0f, 0.0f, 0.0f});
    for (std::size_t i = 0; i < n; ++i)
        skin.joints[i] = {std::uint16_t(label[i]), std::uint16_t(label[i]), std::uint16_t(label[i]), std::uint16_t(label[i])};

    // 2. Alternate weights and transforms.
    for (int iteration = 0; iteration < iterations; ++iteration) {
        // Weights: per vertex, over its four best single bones.
        for (std::size_t i = 0; i < n; ++i)
            solveVertexWeights(skin, rest, frames, i, bestSingleBones(skin, rest, frames, i, 4), false);
        updateBoneTransforms(skin, rest, frames, 0);
    }

    measureSkinError(skin, rest, frames);
    return skin;
}

RigSkinFit fitHelperBones(std::span<const Vec3f> bind, const std::vector<std::vector<Vec3f>>& frames,
                          const SourceSkin& source, int helpers, int iterations) {
    RigSkinFit fit;
    SkinFit& skin = fit.skin;
    const std::size_t n = bind.size(), fcount = frames.size();
    const std::size_t joints = source.transforms.empty() ? 0 : source.transforms.front().size();
    fit.sourceJoints = int(joints);
    skin.bones = int(joints);
    skin.transforms = source.transforms;
    skin.joints = source.joints;
    skin.weights = source.weights;
    if (n == 0 || fcount == 0 || joints == 0)
        return fit;

    // 1. Where the rig alone misses: each vertex's squared error over the clip.
    //    What float positions cannot tell apart counts as nothing: a rig that is exact gets no helpers.
    std::vector<double> missed(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        double largest = 0.0;
        for (std::size_t f = 0; f < fcount; ++f) {
            missed[i] += (skinnedPosition(skin, bind, f, i) - frames[f][i].cast<double>()).squaredNorm();
            largest = std::max(largest, double(frames[f][i].norm()));
        }
        const double noise = 8.0 * double(std::numeric_limits<float>::epsilon()) * (1.0 + largest);
        if (missed[i] <= double(fcount) * noise * noise)
            missed[i] = 0.0;
    }

    // 2. Seeds: k-means++ on the trajectories, where a vertex's distance to the chosen seeds starts at what the
    //    rig misses there: the seeds go where the rig is wrong, spread over the parts that move differently.
    auto distance2 = [&](std::size_t a, std::size_t b) {
        double d = (bind[a] - bind[b]).cast<double>().squaredNorm();
        for (const auto& frame : frames)
            d += (frame[a] - frame[b]).cast<double>().squaredNorm();
        return d;
    };
    const std::size_t wanted = std::size_t(std::clamp<std::ptrdiff_t>(helpers, 0, std::ptrdiff_t(std::min<std::size_t>(n, 65535 - joints))));
    Random random;
    std::vector<std::size_t> centres;
    std::vector<double> nearest = missed;
    while (centres.size() < wanted) {
        const double total = std::accumulate(nearest.begin(), nearest.end(), 0.0);
        if (!(total > 0.0))
            break;
        double pick = random.uniform() * total;
        std::size_t chosen = n - 1;
        for (std::size_t i = 0; i < n; ++i)
            if ((pick -= nearest[i]) <= 0.0) {
                chosen = i;
                break;
            }
        centres.push_back(chosen);
        for (std::size_t i = 0; i < n; ++i)
            nearest[i] = std::min(nearest[i], distance2(i, chosen));
    }
    const std::size_t h = centres.size();
    if (h == 0) {
        measureSkinError(skin, bind, frames);
        return fit;
    }
    const std::size_t k = joints + h;
    skin.bones = int(k);
    for (auto& frame : skin.transforms)
        frame.resize(k);

    // 3. Rigid clustering rounds (Le & Deng's seeding): each vertex to the rig (label h) or to the helper that
    //    carries it best alone, then each helper's cluster fitted rigidly per frame.
    std::vector<std::size_t> label(n, h);
    for (std::size_t i = 0; i < n; ++i) {
        double best = missed[i];
        for (std::size_t c = 0; c < h; ++c)
            if (const double d = distance2(i, centres[c]); d < best) {
                best = d;
                label[i] = c;
            }
    }
    auto fitClusters = [&] {
        std::vector<std::vector<std::size_t>> members(h);
        for (std::size_t i = 0; i < n; ++i)
            if (label[i] < h)
                members[label[i]].push_back(i);
        for (std::size_t f = 0; f < fcount; ++f)
            for (std::size_t c = 0; c < h; ++c)
                skin.transforms[f][joints + c] = fitRigid(bind, frames[f], members[c]);
    };
    for (int round = 0; round < 4; ++round) {
        fitClusters();
        for (std::size_t i = 0; i < n; ++i) {
            double best = missed[i];
            label[i] = h;
            for (std::size_t c = 0; c < h; ++c)
                if (const double e = singleBoneError(skin, bind, frames, i, joints + c); e < best) {
                    best = e;
                    label[i] = c;
                }
        }
    }
    fitClusters();

    // 4. Weights (over the vertex's present bones and the best single ones; never worse than now) and helper
    //    transforms (the source joints held) in turn.
    for (int iteration = 0; iteration < iterations; ++iteration) {
        for (std::size_t i = 0; i < n; ++i) {
            std::vector<std::size_t> candidates;
            for (std::size_t s = 0; s < 4; ++s)
                if (skin.weights[i][s] > 0.0f &&
                    std::find(candidates.begin(), candidates.end(), skin.joints[i][s]) == candidates.end())
                    candidates.push_back(skin.joints[i][s]);
            for (std::size_t j : bestSingleBones(skin, bind, frames, i, kMostCandidates))
                if (candidates.size() < kMostCandidates && std::find(candidates.begin(), candidates.end(), j) == candidates.end())
                    candidates.push_back(j);
            solveVertexWeights(skin, bind, frames, i, candidates, true);
        }
        updateBoneTransforms(skin, bind, frames, joints);
    }

    // 5. Helpers nobody weighs are dropped; each kept one gets its parent (the source joint weighing most where
    //    it acts, by the source's own weights) and its centre.
    std::vector<double> weighs(h, 0.0);
    std::vector<Vec3> centre(h, Vec3::Zero());
    std::vector<std::vector<double>> parentScore(h, std::vector<double>(joints, 0.0));
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t s = 0; s < 4; ++s)
            if (const std::size_t b = skin.joints[i][s]; b >= joints && skin.weights[i][s] > 0.0f) {
                const double w = skin.weights[i][s];
                weighs[b - joints] += w;
                centre[b - joints] += w * bind[i].cast<double>();
                for (std::size_t t = 0; t < 4; ++t)
                    parentScore[b - joints][source.joints[i][t]] += w * double(source.weights[i][t]);
            }
    std::vector<std::uint16_t> renumber(k);
    for (std::size_t j = 0; j < joints; ++j)
        renumber[j] = std::uint16_t(j);
    std::size_t kept = joints;
    for (std::size_t c = 0; c < h; ++c) {
        if (weighs[c] <= 0.0)
            continue;
        renumber[joints + c] = std::uint16_t(kept);
        for (auto& frame : skin.transforms)
            frame[kept] = frame[joints + c];
        const auto& score = parentScore[c];
        fit.helperParent.push_back(int(std::max_element(score.begin(), score.end()) - score.begin()));
        fit.helperCentre.push_back(centre[c] / weighs[c]);
        ++kept;
    }
    for (auto& frame : skin.transforms)
        frame.resize(kept);
    for (auto& slots : skin.joints)
        for (auto& j : slots)
            j = renumber[j];
    skin.bones = int(kept);
    measureSkinError(skin, bind, frames);
    return fit;
}

void measureSkinError(SkinFit& skin, std::span<const Vec3f> rest, const std::vector<std::vector<Vec3f>>& frames) {
    double sum2 = 0.0;
    skin.maxError = 0.0;
    for (std::size_t f = 0; f < frames.size(); ++f)
        for (std::size_t i = 0; i < rest.size(); ++i) {
            const double e = (skinnedPosition(skin, rest, f, i) - frames[f][i].cast<double>()).norm();
            sum2 += e * e;
            skin.maxError = std::max(skin.maxError, e);
        }
    skin.rmsError = frames.empty() || rest.empty() ? 0.0 : std::sqrt(sum2 / double(rest.size() * frames.size()));
}

void roundSkinWeights(SkinFit& skin, int steps) {
    for (std::array<float, 4>& w : skin.weights) {
        // Largest remainder: each weight down to a whole number of steps, then the steps still missing go to
        // the weights that lost most, so the four sum to exactly `steps`.
        double sum = 0.0;
        for (float x : w)
            sum += double(x);
        std::array<int, 4> whole{};
        std::array<double, 4> lost{};
        int given = 0;
        for (std::size_t s = 0; s < 4; ++s) {
            const double exact = sum > 0.0 ? double(w[s]) / sum * steps : (s == 0 ? double(steps) : 0.0);
            whole[s] = int(std::floor(exact));
            lost[s] = exact - whole[s];
            given += whole[s];
        }
        for (; given < steps; ++given) {
            std::size_t most = 0;
            for (std::size_t s = 1; s < 4; ++s)
                if (lost[s] > lost[most])
                    most = s;
            ++whole[most];
            lost[most] = -1.0;
        }
        for (std::size_t s = 0; s < 4; ++s)
            w[s] = float(whole[s]) / float(steps);
    }
}

}  // namespace softtouch
