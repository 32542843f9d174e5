#pragma once
// Feature alignment (SVO): a reference keyframe patch is warped by the affine map predicted
// from the landmark depth and the two poses, then a 2-D Lucas-Kanade (translation + intensity
// offset, inverse compositional) refines the feature's position in the current image.
#include <array>

#include <Eigen/Core>

#include "hdvio/core/lie.h"
#include "hdvio/core/camera_model.h"
#include "hdvio/frontend/pyramid.h"

namespace hdvio::frontend {

constexpr int kAlignPatch = 8;                       // aligned patch is 8x8
constexpr int kAlignHalf = kAlignPatch / 2;
constexpr int kBorderedPatch = kAlignPatch + 2;      // plus one pixel of border for gradients
using BorderedPatch = std::array<float, kBorderedPatch * kBorderedPatch>;

// Maps pixel offsets on the reference feature's pyramid level to level-0 pixel offsets in the
// current image (SVO's convention), assuming the point lies at depth_ref along f_ref (fronto-parallel patch).
Eigen::Matrix2d affineWarp(const CameraModel& camera, const Vec2& px_ref, const Vec3& f_ref,
                           double depth_ref, int level_ref, const Pose& T_cur_ref);

// Pyramid level whose resolution best matches the warped patch (SVO: det(A) shrinks 4x a level).
int bestSearchLevel(const Eigen::Matrix2d& A_cur_ref, int max_level);

// Samples the reference patch (with border) as it will appear on search_level of the current
// image. False if the patch leaves the reference image.
bool warpPatch(const Eigen::Matrix2d& A_cur_ref, const cv::Mat& ref_img, const Vec2& px_ref,
               int level_ref, int search_level, BorderedPatch* patch);

// The reference patch as it appears on `search_level` of the current image, sampled from the
// reference pyramid's level whose resolution matches there: level_ref itself when search_level
// is the level bestSearchLevel picks for A_cur_ref, a coarser (finer) one for a search on a
// coarser (finer) level, so the patch is neither aliased nor blurred.
bool warpPatchFromPyramid(const Eigen::Matrix2d& A_cur_ref, const Pyramid& ref_pyramid,
                          const Vec2& px_ref, int level_ref, int search_level, BorderedPatch* patch);

// Refines *px (a pixel of img, i.e. of the search level) in place. False if it did not converge
// or left the image.
bool align2D(const cv::Mat& img, const BorderedPatch& ref_patch, int max_iterations, Vec2* px);

// Coarse to fine: a feature aligned on `level` of the current pyramid (*p in that level's
// pixels) is aligned again on each finer level down to 0, against the patch warped for that
// level, as long as the finer alignment converges within one pixel of the coarser level's
// result. A coarse level has the wide basin a search needs, level 0 the precision a
// measurement needs. Returns the finest level reached; *p is in its pixels.
int refineToFinerLevels(const Pyramid& cur, const Eigen::Matrix2d& A_cur_ref,
                        const Pyramid& ref_pyramid, const Vec2& px_ref, int level_ref, int level,
                        Vec2* p);

// Zero-mean sum of squared differences between the patch interior and img around integer (x,y).
double zmssd(const cv::Mat& img, const BorderedPatch& ref_patch, int x, int y);

}  // namespace hdvio::frontend
