#pragma once
// Novel-view image metrics: PSNR, SSIM, covered-pixel PSNR and coverage.
#include <opencv2/core.hpp>

namespace multimodal_nvs {

/// The NVS metrics of the paper's protocol on 8-bit images of equal size and channel count.
/// Throws InputError when the images disagree in size or type.

/// PSNR with data range 255 and the MSE over all pixels and channels; +inf for identical images.
double psnr(const cv::Mat& a, const cv::Mat& b);

/// SSIM with an 11x11 Gaussian window (sigma 1.5), data range 255, K1 = 0.01, K2 = 0.03,
/// population (not sample) covariances, the mean over the image without the 5-pixel border the
/// window does not fit in, computed per channel and averaged — the definition of
/// skimage.metrics.structural_similarity(gaussian_weights=True, sigma=1.5,
/// use_sample_covariance=False, data_range=255, channel_axis=-1).
double ssim(const cv::Mat& a, const cv::Mat& b);

/// PSNR over the pixels where `mask` is nonzero only (all channels); NaN when none is.
double coveredPsnr(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask);

/// Fraction of nonzero pixels of `mask`.
double coverage(const cv::Mat& mask);

}  // namespace multimodal_nvs
