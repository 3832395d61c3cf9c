// The one file that includes OpenCV: the camera-model fits behind the extern "C"
// interface of image.h (pictures are drawn through cairo: canvas_cairo.c).
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

extern "C" {
#include "sparselens/image.h"
#include "sparselens/outfile.h"
}

namespace {

template <typename P3, typename P2>
int gather(int nviews, const size_t *counts, const double *obj, const double *pix,
           std::vector<std::vector<P3>> &o, std::vector<std::vector<P2>> &p, lens_err *err)
{
    size_t k = 0;
    for (int v = 0; v < nviews; v++) {
        if (counts[v] < 6) {
            lens_errf(err, nullptr, 0, "camera fit: view %d has %zu points, need at least 6", v,
                      counts[v]);
            return -1;
        }
        std::vector<P3> ov;
        std::vector<P2> pv;
        for (size_t i = 0; i < counts[v]; i++, k++) {
            if (!std::isfinite(obj[3 * k] + obj[3 * k + 1] + obj[3 * k + 2] + pix[2 * k] +
                               pix[2 * k + 1])) {
                lens_errf(err, nullptr, 0, "camera fit: point %zu is not finite", k);
                return -1;
            }
            ov.emplace_back(obj[3 * k], obj[3 * k + 1], obj[3 * k + 2]);
            pv.emplace_back(pix[2 * k], pix[2 * k + 1]);
        }
        o.push_back(ov);
        p.push_back(pv);
    }
    return 0;
}

// Residuals by reprojecting through the fitted model (rms and max, pixels).
template <typename P2>
void residuals(const std::vector<std::vector<P2>> &p, const std::vector<std::vector<P2>> &q,
               cv_camera_fit *fit)
{
    double s = 0, mx = 0;
    size_t n = 0;
    for (size_t v = 0; v < p.size(); v++)
        for (size_t i = 0; i < p[v].size(); i++) {
            double d = std::hypot(p[v][i].x - q[v][i].x, p[v][i].y - q[v][i].y);
            s += d * d;
            mx = std::fmax(mx, d);
            n++;
        }
    fit->rms = std::sqrt(s / (double)n);
    fit->max_err = mx;
}

} // namespace

extern "C" {

int cv_fit_brown(int width, int height, double f_px, int nviews, const size_t *counts,
                 const double *obj, const double *pix, cv_camera_fit *fit, lens_err *err)
{
    std::vector<std::vector<cv::Point3f>> o;
    std::vector<std::vector<cv::Point2f>> p;
    if (gather(nviews, counts, obj, pix, o, p, err) != 0)
        return -1;
    try {
        cv::Mat K = (cv::Mat_<double>(3, 3) << f_px, 0, width / 2.0, 0, f_px, height / 2.0, 0, 0, 1);
        cv::Mat D = cv::Mat::zeros(5, 1, CV_64F);
        std::vector<cv::Mat> rv, tv;
        int flags = cv::CALIB_USE_INTRINSIC_GUESS | cv::CALIB_FIX_PRINCIPAL_POINT |
                    cv::CALIB_FIX_ASPECT_RATIO;
        cv::TermCriteria tc(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-12);
        cv::calibrateCamera(o, p, cv::Size(width, height), K, D, rv, tv, flags, tc);
        fit->fx = K.at<double>(0, 0);
        fit->fy = K.at<double>(1, 1);
        fit->cx = K.at<double>(0, 2);
        fit->cy = K.at<double>(1, 2);
        for (int i = 0; i < 5; i++)
            fit->k[i] = D.at<double>(i);
        std::vector<std::vector<cv::Point2f>> q(p.size());
        for (size_t v = 0; v < o.size(); v++)
            cv::projectPoints(o[v], rv[v], tv[v], K, D, q[v]);
        residuals(p, q, fit);
    } catch (const cv::Exception &e) {
        lens_errf(err, nullptr, 0, "OpenCV calibrateCamera failed: %s", e.err.c_str());
        return -1;
    }
    return 0;
}

int cv_fit_fisheye(int width, int height, double f_px, int fix_focal, int nviews,
                   const size_t *counts, const double *obj, const double *pix, cv_camera_fit *fit,
                   lens_err *err)
{
    std::vector<std::vector<cv::Point3d>> o;
    std::vector<std::vector<cv::Point2d>> p;
    if (gather(nviews, counts, obj, pix, o, p, err) != 0)
        return -1;
    try {
        cv::Matx33d K(f_px, 0, width / 2.0, 0, f_px, height / 2.0, 0, 0, 1);
        cv::Vec4d D(0, 0, 0, 0);
        std::vector<cv::Vec3d> rv, tv;
        int flags = cv::fisheye::CALIB_USE_INTRINSIC_GUESS | cv::fisheye::CALIB_FIX_SKEW |
                    cv::fisheye::CALIB_FIX_PRINCIPAL_POINT |
                    cv::fisheye::CALIB_RECOMPUTE_EXTRINSIC |
                    (fix_focal ? cv::fisheye::CALIB_FIX_FOCAL_LENGTH : 0);
        cv::TermCriteria tc(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-12);
        cv::fisheye::calibrate(o, p, cv::Size(width, height), K, D, rv, tv, flags, tc);
        fit->fx = K(0, 0);
        fit->fy = K(1, 1);
        fit->cx = K(0, 2);
        fit->cy = K(1, 2);
        for (int i = 0; i < 4; i++)
            fit->k[i] = D[i];
        fit->k[4] = 0;
        std::vector<std::vector<cv::Point2d>> q(p.size());
        for (size_t v = 0; v < o.size(); v++)
            cv::fisheye::projectPoints(o[v], q[v], rv[v], tv[v], K, D);
        residuals(p, q, fit);
    } catch (const cv::Exception &e) {
        lens_errf(err, nullptr, 0, "OpenCV fisheye::calibrate failed: %s", e.err.c_str());
        return -1;
    }
    return 0;
}

} // extern "C"
