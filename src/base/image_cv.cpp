// The one file that includes OpenCV: drawing, PNG input/output and the camera-model
// fits, behind the extern "C" interface of image.h.
//
// The canvas is CV_32FC3 in OpenCV's BGR order. OpenCV antialiases only on 8-bit
// images, so every primitive is rasterised into an 8-bit coverage mask over its
// bounding box and blended into the float canvas with that coverage as alpha.
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <vector>

extern "C" {
#include "sparselens/image.h"
#include "sparselens/outfile.h"
}

struct img_canvas {
    cv::Mat m; // CV_32FC3, BGR, values in [0, 1]
};

namespace {

// Sub-pixel coordinates for OpenCV's integer drawing API.
const int kShift = 4;
const double kScale = 16.0;

cv::Point fixpt(double x, double y, const cv::Point &off)
{
    return cv::Point((int)std::lround((x - off.x) * kScale), (int)std::lround((y - off.y) * kScale));
}

// Rasterises draw() into a coverage mask over box (clipped to the canvas) and blends.
void blend(img_canvas *c, cv::Rect box, const double rgb[3], double alpha,
           const std::function<void(cv::Mat &, const cv::Point &)> &draw)
{
    box &= cv::Rect(0, 0, c->m.cols, c->m.rows);
    if (box.width <= 0 || box.height <= 0)
        return;
    cv::Mat mask = cv::Mat::zeros(box.height, box.width, CV_8UC1);
    draw(mask, box.tl());
    for (int y = 0; y < box.height; y++) {
        const unsigned char *mp = mask.ptr<unsigned char>(y);
        cv::Vec3f *ip = c->m.ptr<cv::Vec3f>(y + box.y) + box.x;
        for (int x = 0; x < box.width; x++) {
            if (!mp[x])
                continue;
            float a = (float)(alpha * mp[x] / 255.0);
            for (int k = 0; k < 3; k++)
                ip[x][k] = ip[x][k] * (1 - a) + a * (float)rgb[2 - k];
        }
    }
}

cv::Rect bbox(double x0, double y0, double x1, double y1, double pad)
{
    int ax = (int)std::floor(std::fmin(x0, x1) - pad), ay = (int)std::floor(std::fmin(y0, y1) - pad);
    int bx = (int)std::ceil(std::fmax(x0, x1) + pad), by = (int)std::ceil(std::fmax(y0, y1) + pad);
    return cv::Rect(ax, ay, bx - ax + 1, by - ay + 1);
}

bool finite_all(std::initializer_list<double> v)
{
    for (double d : v)
        if (!std::isfinite(d) || std::fabs(d) > 1e7)
            return false;
    return true;
}

const int kFont = cv::FONT_HERSHEY_SIMPLEX;

double font_scale(double height)
{
    int base = 0;
    cv::Size s = cv::getTextSize("H", kFont, 1.0, 1, &base);
    return height / s.height;
}

} // namespace

extern "C" {

img_canvas *img_new(int width, int height, const double bg[3])
{
    if (width <= 0 || height <= 0)
        return nullptr;
    try {
        img_canvas *c = new img_canvas;
        c->m = cv::Mat(height, width, CV_32FC3, cv::Scalar(bg[2], bg[1], bg[0]));
        return c;
    } catch (...) {
        return nullptr;
    }
}

void img_free(img_canvas *c) { delete c; }
int img_width(const img_canvas *c) { return c->m.cols; }
int img_height(const img_canvas *c) { return c->m.rows; }

void img_line(img_canvas *c, double x0, double y0, double x1, double y1, const double rgb[3],
              double thickness)
{
    if (!finite_all({x0, y0, x1, y1}))
        return;
    int t = std::max(1, (int)std::lround(thickness));
    blend(c, bbox(x0, y0, x1, y1, t + 2), rgb, 1.0, [&](cv::Mat &m, const cv::Point &o) {
        cv::line(m, fixpt(x0, y0, o), fixpt(x1, y1, o), cv::Scalar(255), t, cv::LINE_AA, kShift);
    });
}

void img_circle(img_canvas *c, double cx, double cy, double r, const double rgb[3],
                double thickness)
{
    if (!finite_all({cx, cy, r}) || r <= 0)
        return;
    int t = thickness > 0 ? std::max(1, (int)std::lround(thickness)) : cv::FILLED;
    blend(c, bbox(cx - r, cy - r, cx + r, cy + r, std::fmax(thickness, 1) + 2), rgb, 1.0,
          [&](cv::Mat &m, const cv::Point &o) {
              cv::circle(m, fixpt(cx, cy, o), (int)std::lround(r * kScale), cv::Scalar(255), t,
                         cv::LINE_AA, kShift);
          });
}

void img_rect(img_canvas *c, double x0, double y0, double x1, double y1, const double rgb[3],
              double thickness)
{
    if (!finite_all({x0, y0, x1, y1}))
        return;
    int t = thickness > 0 ? std::max(1, (int)std::lround(thickness)) : cv::FILLED;
    blend(c, bbox(x0, y0, x1, y1, std::fmax(thickness, 1) + 2), rgb, 1.0,
          [&](cv::Mat &m, const cv::Point &o) {
              cv::rectangle(m, fixpt(x0, y0, o), fixpt(x1, y1, o), cv::Scalar(255), t,
                            cv::LINE_AA, kShift);
          });
}

void img_polygon(img_canvas *c, const double *xy, int n, const double rgb[3], double alpha)
{
    if (n < 3)
        return;
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int i = 0; i < n; i++) {
        if (!finite_all({xy[2 * i], xy[2 * i + 1]}))
            return;
        x0 = std::fmin(x0, xy[2 * i]), x1 = std::fmax(x1, xy[2 * i]);
        y0 = std::fmin(y0, xy[2 * i + 1]), y1 = std::fmax(y1, xy[2 * i + 1]);
    }
    blend(c, bbox(x0, y0, x1, y1, 2), rgb, alpha, [&](cv::Mat &m, const cv::Point &o) {
        std::vector<cv::Point> pts;
        for (int i = 0; i < n; i++)
            pts.push_back(fixpt(xy[2 * i], xy[2 * i + 1], o));
        cv::fillPoly(m, std::vector<std::vector<cv::Point>>{pts}, cv::Scalar(255), cv::LINE_AA, kShift);
    });
}

void img_dot(img_canvas *c, double x, double y, double radius, const double rgb[3], double alpha)
{
    if (!finite_all({x, y, radius}) || radius <= 0)
        return;
    // Coverage of a disc with a one-pixel linear edge: cheap and smooth.
    int x0 = (int)std::floor(x - radius - 1), x1 = (int)std::ceil(x + radius + 1);
    int y0 = (int)std::floor(y - radius - 1), y1 = (int)std::ceil(y + radius + 1);
    for (int py = std::max(y0, 0); py <= std::min(y1, c->m.rows - 1); py++) {
        cv::Vec3f *ip = c->m.ptr<cv::Vec3f>(py);
        for (int px = std::max(x0, 0); px <= std::min(x1, c->m.cols - 1); px++) {
            double d = std::hypot(px + 0.5 - x, py + 0.5 - y);
            double cov = std::fmin(1.0, std::fmax(0.0, radius + 0.5 - d));
            if (cov <= 0)
                continue;
            float a = (float)(alpha * cov);
            for (int k = 0; k < 3; k++)
                ip[px][k] = ip[px][k] * (1 - a) + a * (float)rgb[2 - k];
        }
    }
}

double img_text_width(const char *text, double height)
{
    int base = 0;
    double s = font_scale(height);
    int t = std::max(1, (int)std::lround(height / 9));
    return cv::getTextSize(text, kFont, s, t, &base).width;
}

void img_text(img_canvas *c, double x, double y, const char *text, double height,
              const double rgb[3])
{
    if (!finite_all({x, y, height}) || !text || !*text)
        return;
    double s = font_scale(height);
    int t = std::max(1, (int)std::lround(height / 9));
    int base = 0;
    cv::Size sz = cv::getTextSize(text, kFont, s, t, &base);
    blend(c, bbox(x, y - sz.height - t, x + sz.width, y + base, t + 2), rgb, 1.0,
          [&](cv::Mat &m, const cv::Point &o) {
              cv::putText(m, text, cv::Point((int)std::lround(x - o.x), (int)std::lround(y - o.y)),
                          kFont, s, cv::Scalar(255), t, cv::LINE_AA);
          });
}

int img_write_png(const img_canvas *c, const char *path, lens_err *err)
{
    std::vector<unsigned char> buf;
    try {
        cv::Mat m8;
        c->m.convertTo(m8, CV_8UC3, 255.0);
        if (!cv::imencode(".png", m8, buf)) {
            lens_errf(err, path, 0, "cannot encode PNG");
            return -1;
        }
    } catch (const cv::Exception &e) {
        lens_errf(err, path, 0, "cannot encode PNG: %s", e.what());
        return -1;
    }
    char tmp[4096];
    if (outfile_tmp_path(path, tmp, sizeof tmp) != 0) {
        lens_errf(err, path, 0, "cannot make a temporary file name");
        return -1;
    }
    FILE *f = std::fopen(tmp, "wb");
    if (!f) {
        lens_errf(err, path, 0, "cannot write: %s", std::strerror(errno));
        return -1;
    }
    size_t n = std::fwrite(buf.data(), 1, buf.size(), f);
    int bad = n != buf.size() || std::fflush(f) != 0;
    if (std::fclose(f) != 0 || bad) {
        outfile_discard_path(tmp);
        lens_errf(err, path, 0, "write error");
        return -1;
    }
    return outfile_commit_path(tmp, path, err);
}

int img_png_info(const char *path, int *width, int *height, long *nonblank, lens_err *err)
{
    // OpenCV logs a warning for a missing file: check first, report through err.
    FILE *f = std::fopen(path, "rb");
    if (!f) {
        lens_errf(err, path, 0, "cannot open: %s", std::strerror(errno));
        return -1;
    }
    std::fclose(f);
    try {
        cv::Mat m = cv::imread(path, cv::IMREAD_COLOR);
        if (m.empty()) {
            lens_errf(err, path, 0, "cannot read as an image");
            return -1;
        }
        *width = m.cols;
        *height = m.rows;
        cv::Vec3b corner = m.at<cv::Vec3b>(0, 0);
        long n = 0;
        for (int y = 0; y < m.rows; y++)
            for (int x = 0; x < m.cols; x++)
                n += m.at<cv::Vec3b>(y, x) != corner;
        *nonblank = n;
        return 0;
    } catch (const cv::Exception &e) {
        lens_errf(err, path, 0, "cannot read: %s", e.what());
        return -1;
    }
}

} // extern "C"

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
