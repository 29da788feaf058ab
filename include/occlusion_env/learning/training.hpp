// Training the multi-task network (Section 5.2, Eq. 10-12) on a BOP dataset written by
// occlusion_dataset: data in memory as tensors, AdamW with a cosine schedule, soft Dice on the
// occlusion map plus a direction loss on the gradient and escape labels, colour jitter and
// horizontal flips with the label transform, validation every epoch, a checkpoint every epoch
// (resumable), the best model by validation IoU.
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "occlusion_env/learning/multitask_unet.hpp"

namespace occlusion_env {
namespace learning {

/// Directions of the one-step circle in a frame's shortest first moves (the oracle's default
/// circle_directions, which the dataset tools use).
constexpr int kShortestMoveDirections = 64;

/// The frames of a dataset at the network's resolution.
struct Samples {
  // Held compactly, so that 100,000 frames fit in memory at 96 px: the inputs as 16-bit floats
  // (rounding the network input by at most 1/16 of a grey level), the masks as bytes; a batch is
  // made of 32-bit floats.
  torch::Tensor inputs;          // [N, C, S, S] half, C = 4 or 5 (network_input.hpp)
  torch::Tensor masks;           // [N, 1, S, S] uint8 0 / 1
  torch::Tensor gradient;        // [N, 2] (sin, cos) of the descent direction
  torch::Tensor gradient_valid;  // [N] 0 / 1
  torch::Tensor escape;          // [N, 2] (sin, cos) of the oracle's first step
  torch::Tensor escape_valid;    // [N] 0 / 1
  torch::Tensor oracle_steps;    // [N] int32: the label's fewest steps to a clear view, -1 none
  // [N, kShortestMoveDirections] uint8: the first moves as short as the oracle's
  // (FrameLabels::shortest_first_moves); all 0 where a frame has none recorded.
  torch::Tensor shortest_moves;
  int64_t size() const { return inputs.defined() ? inputs.size(0) : 0; }
};

struct TrainingData {
  Samples train, validation;
  nlohmann::json dataset_manifest;              // the first dataset's
  std::string dataset_dir;                      // the first dataset
  std::vector<std::string> extra_dataset_dirs;  // further datasets, if any
};

/// The fraction of a network pixel's area that must be occluded for it to be labelled occluded,
/// in the paper's masks and in the validation IoU of every table.
constexpr double kPaperMaskCoverage = 0.5;

/// Reads every complete scene of the dataset in `dir` as the network sees it (`format`), split by
/// the manifest's scene-wise train/val split; `max_scenes` > 0 keeps only the first ones. Refuses
/// datasets with test seeds or models outside the train split (InvalidArgumentError).
TrainingData loadTrainingData(const std::string& dir, const InputFormat& format,
                              int max_scenes = 0);

/// The same for several datasets (dirs[0] first), each split by its own manifest: e.g. a
/// dataset with oracle labels and a larger one without them made with `--validation 0`, which
/// adds training frames and leaves the validation frames as they were. Also refuses a scene seed
/// that is in two of them. `max_scenes` applies to each. `negatives` > 0 appends that fraction of
/// the training frames' count as frames with nothing to occlude (learning/negative_frames.hpp):
/// every other one a bare surface, the others one object alone from a training frame drawn at
/// random; their mask is empty and they have no direction labels. `seed` draws them. The
/// validation frames are the datasets' alone. A network pixel's label is occluded where at least
/// `mask_coverage` of its area is occluded in the frame's mask (TrainingOptions::mask_coverage),
/// in the training and the validation frames alike.
TrainingData loadTrainingData(const std::vector<std::string>& dirs, const InputFormat& format,
                              int max_scenes = 0, double negatives = 0.0, std::uint64_t seed = 1,
                              double mask_coverage = kPaperMaskCoverage);

/// Every frame (of training and validation scenes alike) of datasets that a model was not trained
/// on, at `size` px: a check of the model beyond the validation scenes by which it was chosen.
/// Refuses (InvalidArgumentError) a dataset that `model_manifest` lists as trained on (by path)
/// or whose options equal those of the model's first dataset. Labels as loadTrainingData's at
/// `mask_coverage`. With `conditions`, what each frame was seen under, row by row: "<world>,
/// <depth sensor>" from its labels' scene setup (e.g. "room, realsense_d435"), "not recorded"
/// for frames whose labels name none.
/// With `scene_seeds`, the seed of each frame's scene, row by row.
Samples loadCheckFrames(const std::vector<std::string>& dirs, const InputFormat& format,
                        const nlohmann::json& model_manifest,
                        double mask_coverage = kPaperMaskCoverage,
                        std::vector<std::string>* conditions = nullptr,
                        std::vector<std::uint64_t>* scene_seeds = nullptr);

struct TrainingOptions {
  NetworkConfig network;
  int epochs = 15;
  int batch_size = 32;
  double learning_rate = 1e-3;  // AdamW, cosine-annealed to 0 over all epochs (per batch)
  double weight_decay = 1e-5;
  double dice_weight = 1.0;       // beta_1 (Eq. 12)
  double direction_weight = 1.0;  // beta_2, for each direction head (and the escape-bins head)
  double bce_weight = 0.0;  // weight of a pixel-wise binary cross-entropy on the occlusion map,
                            // added to the paper's loss (0: the paper's loss)
  std::string direction_loss = "mse";  // mse | smooth_l1 (beta 0.01: the paper's -L1 variant)
  // With network.escape_bins: the escape-bins head's cross-entropy (weighted by
  // direction_weight) is against a von Mises bump of this concentration around the label.
  double escape_bin_concentration = 8.0;
  // With network.escape_bins, what that cross-entropy aims at: "label" (the bump above) or
  // "shortest_moves" (every first move as short as the oracle's, shortestMoveTargets(), where a
  // frame records them; the bump elsewhere).
  std::string escape_bin_targets = "label";
  bool augment = true;  // colour jitter and horizontal flips
  // With augment: each frame moved by up to this fraction of its size in x and y (uniform, whole
  // pixels), labels unchanged, the uncovered border the void's (black, no depth): an estimate that
  // follows the content, not where occlusion usually is in a centred scene. 0: no moves.
  double shift = 0.0;
  // With augment: this fraction of the training frames, drawn per batch, lose every depth reading
  // (dropDepth): the network must then find occlusion from colour alone, as where a sensor reads
  // nothing of objects nearer than its minimum range. 0: none.
  double depth_dropout = 0.0;
  // Frames with nothing to occlude added to the training frames, as a fraction of their count
  // (loadTrainingData's `negatives`; read by the tool that loads the data). 0: none.
  double negatives = 0.0;
  // A network pixel is labelled occluded where at least this fraction of its area is occluded in
  // the frame's mask (loadTrainingData's `mask_coverage`): 0.5 the paper's; a small one labels
  // every pixel that holds any occlusion, for an estimate that must not miss a sliver (the camera
  // bridge's, which stops on views with no occluded pixel at all).
  double mask_coverage = kPaperMaskCoverage;
  std::uint64_t seed = 1;
  int threads = 0;  // libtorch threads; 0 = the machine's cores
  // A model file (saveModel) of the same network to start from instead of random weights: the
  // schedule and the optimizer start afresh on it (a warm restart). Empty: random weights.
  std::string init_from;
  // Also keep every epoch's weights as epoch_<k>.pt (with its manifest) beside best.pt, so that a
  // model can be chosen afterwards by something other than validation IoU (e.g. the agent's steps
  // on validation scenes, scripts/dagger.sh). Does not change the run.
  bool keep_epochs = false;

  /// Throws InvalidArgumentError naming the first bad option (the tables' ranges and choices).
  void validate() const;
  /// What a run records (checkpoint identity, manifests' "training"): every option by its table
  /// name, the network as "network", init_from only when set; threads (how, not what) left out.
  nlohmann::json toJson() const;
};

/// Moves each frame of `inputs` (N x C x S x S, learning/network_input.hpp) and its mask (N x 1 x S
/// x S) by whole pixels drawn uniformly from [-shift * S, shift * S] in x and y (torch's
/// generator); the uncovered border becomes the void's input (black, no depth) and mask 0.
void shiftFrames(torch::Tensor& inputs, torch::Tensor& masks, double shift);

/// Each frame of `inputs` (N x C x S x S, learning/network_input.hpp) with this probability
/// (torch's generator) reads no depth anywhere: its depth channel as far and its valid-fraction
/// channel, if it has one, as nothing read, as the void's; RGB kept. 0 draws nothing.
void dropDepth(torch::Tensor& inputs, double probability);

/// The declared options of TrainingOptions but the network (networkConfigTable()), by their
/// manifest names; the flags are occlusion_train's.
const OptionTable<TrainingOptions>& trainingOptionTable();

struct EpochMetrics {
  int epoch = 0;  // 1-based
  double learning_rate = 0.0;
  double train_loss = 0.0;
  double val_dice_loss = 0.0;
  double val_pixel_accuracy = 0.0;  // [0, 1]
  double val_iou = 0.0;             // of the occlusion map, over all validation pixels
  double val_gradient_mse = 0.0;    // ||prediction - (sin, cos)||^2, as Eq. 11
  double val_escape_mse = 0.0;
  double val_gradient_angle_deg = 0.0;  // mean angular error of the normalised prediction
  double val_escape_angle_deg = 0.0;
  double val_escape_bins_angle_deg = 0.0;  // of the escape-bins head's choice; 0 without it
  // The share of the frames with recorded shortest first moves whose move (the circle's
  // direction nearest the head's) is one of them: of the escape head and the escape-bins head
  // (0 without it). 0 when no frame records them.
  double val_escape_shortest_share = 0.0;
  double val_escape_bins_shortest_share = 0.0;
  double seconds = 0.0;
  double images_per_second = 0.0;  // training throughput

  nlohmann::json toJson() const;
};

/// The pooled IoU (sum of intersections / sum of unions over the frames) of the network's
/// occlusion map thresholded at other probabilities than evaluate()'s 0.5: where between sure
/// and eager a model's maps match the labels best.
struct IouByProbability {
  std::vector<double> probabilities;  // in (0, 1); InvalidArgumentError otherwise
  std::vector<double> ious;           // [0, 1], one per probability, filled by evaluate()
};

/// The columns of evaluate()'s occlusion_counts.
constexpr int64_t kOcclusionCounts = 6;

/// Per frame of an occlusion map `predicted` and its label `masks` (both [B, 1, H, W], 1 / 0):
/// [B, kOcclusionCounts] the intersection, the union, the label's pixels, the map's, and the
/// map's false positives within 1 and within 3 pixels of a labelled pixel (Chebyshev distance).
torch::Tensor occlusionCounts(const torch::Tensor& predicted, const torch::Tensor& masks);

/// Validation figures of `network` on `samples` (eval mode, no gradients). Per frame, of the head
/// the predicted-escape agent moves by (the escape-bins head's choice when there is one, else the
/// escape head): with `escape_errors_deg`, its angular error [deg], NaN where a frame has no
/// escape label; with `escape_shortest`, whether its move is one of the frame's shortest first
/// moves (1 / 0), NaN where it records none; with `occlusion_counts`, occlusionCounts() of its
/// occlusion map (logit > 0) and the label [px at the network's size] (sums over the frames of
/// the first two give the IoU); with
/// `iou_by_probability`, the pooled IoU at each of its thresholds, counted in the same pass.
EpochMetrics evaluate(MultiTaskUNet& network, const Samples& samples, int batch_size,
                      const std::string& direction_loss, torch::Tensor* escape_errors_deg = nullptr,
                      torch::Tensor* escape_shortest = nullptr,
                      torch::Tensor* occlusion_counts = nullptr,
                      IouByProbability* iou_by_probability = nullptr);

/// Targets [B, bins] of the escape-bins head from shortest first moves [B, n] (0 / 1, n a
/// multiple of bins; bin k is direction k n / bins): each shortest move weighted by how many
/// directions away the nearest move that is not shortest lies (the middle of a run of shortest
/// moves most, its ends least; a whole circle evenly), normalised to sum 1. Rows without any
/// shortest move at the bins' directions are all 0.
torch::Tensor shortestMoveTargets(const torch::Tensor& shortest_moves, int bins);

/// The shortest first moves [B, n] of the horizontally flipped frames: direction k of the circle
/// mirrors to pi - theta_k, direction n / 2 - k (dataset/labels.hpp).
torch::Tensor mirroredShortestMoves(const torch::Tensor& shortest_moves);

/// Whether the circle's direction nearest each of `directions` [B, 2] (sin, cos) is one of the
/// row's `shortest_moves` [B, n]: [B] float 1 / 0.
torch::Tensor isShortestMove(const torch::Tensor& directions, const torch::Tensor& shortest_moves);

/// `errors_deg` (evaluate()'s escape errors) by how far each frame is from a clear view
/// (`oracle_steps`): rows for 1, 2, 3, 4-5, 6-8 and 9 or more steps and "all", each with frames,
/// mean_deg, median_deg, share_over_45_deg and share_over_90_deg; frames without an escape label
/// (NaN) are left out, and so are rows without frames. Where the escape agent loses its steps.
/// With `shortest` (evaluate()'s escape_shortest), rows also give share_shortest: the share of
/// their frames that record shortest moves whose move is one of them.
nlohmann::json escapeErrorsByOracleSteps(const torch::Tensor& errors_deg,
                                         const torch::Tensor& oracle_steps,
                                         const torch::Tensor& shortest = {});

/// The frames of each condition (`conditions`, one per frame, as loadCheckFrames gives them):
/// their indices in frame order, the conditions in name order.
std::map<std::string, std::vector<int64_t>> framesByCondition(
    const std::vector<std::string>& conditions);

/// evaluate()'s per-frame figures by what the frames were seen under (`conditions`, one per
/// frame, as loadCheckFrames gives them): a row per condition, in name order, with frames,
/// val_iou, labelled_px, predicted_px, precision and recall (from `occlusion_counts`; precision
/// and recall 1 where nothing is predicted or labelled), false_positive_px and the shares of them
/// within 1 and within 3 px of the label (false_positives_within_1px, _within_3px: whether false
/// alarms fatten the labelled occlusion or stand apart from it; absent where there is no false
/// positive), and mean_escape_deg (of `escape_errors_deg`' labelled frames; absent where none is
/// labelled). InvalidArgumentError unless `occlusion_counts` has occlusionCounts()'
/// kOcclusionCounts columns.
/// With `scene_seeds` (one per frame), each row also has its scenes and val_iou_95
/// (sceneBootstrapIou's interval).
nlohmann::json figuresByCondition(const std::vector<std::string>& conditions,
                                  const torch::Tensor& occlusion_counts,
                                  const torch::Tensor& escape_errors_deg,
                                  const std::vector<std::uint64_t>& scene_seeds = {});

/// How far a pooled IoU would move on another sample of as many scenes.
struct IouInterval {
  double low = 0.0, high = 0.0;  // the 2.5th and 97.5th percentiles, fractions
  int scenes = 0;                // distinct scene seeds among the frames
};

/// The 95 % interval of the pooled IoU (sum of intersections / sum of unions) of `frames` (rows
/// of `occlusion_counts`, as evaluate() gives them: columns 0 and 1 are read), by a percentile
/// bootstrap over scenes: the scenes (`scene_seeds`, one per row) drawn again with replacement
/// `draws` times, each with all its frames, since views of one scene err alike. Deterministic for a
/// `seed`. Frames of one seed in two datasets count as one scene: the same objects, placed alike.
IouInterval sceneBootstrapIou(const torch::Tensor& occlusion_counts,
                              const std::vector<std::uint64_t>& scene_seeds,
                              const std::vector<int64_t>& frames, int draws = 2000,
                              std::uint64_t seed = 1);

/// The gap between two sets' pooled IoUs and how far it would move on other scenes.
struct IouGap {
  double gap = 0.0;              // a's pooled IoU minus b's, over the scenes both hold
  double low = 0.0, high = 0.0;  // its 2.5th and 97.5th percentiles
  int scenes = 0;                // the scenes both hold
};

/// The gap of a's pooled IoU over b's (`counts_*`, as evaluate()'s occlusion_counts, one
/// scene seed per row in `seeds_*`) on the scenes both sets hold, and its 95 % interval by a
/// paired bootstrap: the shared scenes drawn with replacement `draws` times, each with all its
/// frames in both sets, since a scene that is hard under one camera tends to be hard under
/// another (the same seed is the same objects, placed alike). Deterministic for a `seed`.
/// InvalidArgumentError when no scene is in both.
IouGap sceneBootstrapIouGap(const torch::Tensor& counts_a,
                            const std::vector<std::uint64_t>& seeds_a,
                            const torch::Tensor& counts_b,
                            const std::vector<std::uint64_t>& seeds_b, int draws = 2000,
                            std::uint64_t seed = 1);

struct TrainingCallbacks {
  std::function<void(int epoch, int batch, int batches)> on_batch;
  std::function<void(const EpochMetrics&)> on_epoch;
};

/// Trains in `run_dir`: checkpoint.pt after every epoch (and resumes from it when present and
/// made with the same options and data), log.csv, best.pt/best.json (by validation IoU), and
/// with keep_epochs epoch_<k>.pt/.json for every epoch. Returns
/// the metrics of every epoch (resumed ones included, from the log). Throws InvalidArgumentError
/// for bad options, data at another size than the network's, and escape_bin_targets
/// shortest_moves on training frames none of which records its shortest first moves.
std::vector<EpochMetrics> train(const TrainingData& data, const TrainingOptions& options,
                                const std::string& run_dir,
                                const TrainingCallbacks& callbacks = {});

/// The BLAS library libtorch's process has mapped (its real path), "" if none is found; and
/// whether it is the slow reference BLAS (Debian's default libblas.so.3).
std::string loadedBlasLibrary();
bool referenceBlasLoaded();

/// Sets libtorch's thread count: `threads`, or the machine's cores when it is 0.
void setLibtorchThreads(int threads);

}  // namespace learning
}  // namespace occlusion_env
