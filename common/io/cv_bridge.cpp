// cv_bridge.cpp — see cv_bridge.h. The project's only C++ file, built alone
// into the module libraster101_cv.so that cv_bridge_load.c opens with dlopen
// when OpenCV is first needed. It exports one symbol, the table at the end.
#include "cv_bridge.h"

#include <opencv2/core.hpp>
#include <opencv2/highgui.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>   // snprintf
#include <cstdlib>  // getenv, malloc
#include <cstring>  // memcpy, strstr
#include <exception>
#include <map>
#include <string>
#include <vector>

#include <unistd.h> // dup, dup2, close

namespace {

void set_err(char *err, int err_size, const std::string &msg) {
    if (err && err_size > 0) std::snprintf(err, (size_t)err_size, "%s", msg.c_str());
}

// Per-window state: the mouse position, filled by highgui's callback, and
// whether the backend has ever answered WND_PROP_AUTOSIZE for the window
// (window_wait_key: how a closed window is told).
struct Mouse {
    int col = -1, row = -1;
    bool autosize_answered = false;
};
std::map<std::string, Mouse> g_mouse;  // highgui itself is process-global

void on_mouse(int event, int x, int y, int, void *user) {
    if (event == cv::EVENT_MOUSEMOVE) {
        auto *m = static_cast<Mouse *>(user);
        m->col = x;
        m->row = y;
    }
}

}  // namespace

// The file bytes of `m` encoded as `ext`, in memory the C side frees (malloc);
// `kind` ("" or "float ") names the encoder in the messages.
static uint8_t *encoded_copy(const char *ext, const cv::Mat &m, const char *kind, size_t *len,
                             char *err, int err_size) {
    std::vector<uchar> buf;
    if (!cv::imencode(ext, m, buf) || buf.empty()) {
        set_err(err, err_size, std::string("OpenCV has no ") + kind + "encoder for '" + ext + "'");
        return nullptr;
    }
    auto *out = static_cast<uint8_t *>(std::malloc(buf.size()));
    if (!out) {
        set_err(err, err_size, std::string("out of memory for the encoded ") + kind + "image");
        return nullptr;
    }
    std::memcpy(out, buf.data(), buf.size());
    *len = buf.size();
    return out;
}

static uint8_t *encode_rgb8(const char *ext, int width, int height, const uint8_t *rgb, size_t *len,
                            char *err, int err_size) {
    try {
        cv::Mat in(height, width, CV_8UC3, const_cast<uint8_t *>(rgb));
        cv::Mat bgr;
        cv::cvtColor(in, bgr, cv::COLOR_RGB2BGR);
        return encoded_copy(ext, bgr, "", len, err, err_size);
    } catch (const std::exception &e) {
        set_err(err, err_size, std::string("the encoder failed: ") + e.what());
        return nullptr;
    }
}

static uint8_t *encode_f32(const char *ext, int width, int height, int channels, const float *data,
                           size_t *len, char *err, int err_size) {
    try {
        if (channels != 1 && channels != 3) {
            set_err(err, err_size, "a float image has 1 or 3 channels");
            return nullptr;
        }
        cv::Mat in(height, width, channels == 1 ? CV_32FC1 : CV_32FC3,
                   const_cast<float *>(data));
        cv::Mat file; /* a new matrix: cvtColor into a view of `in` would write the
                       * caller's data */
        if (channels == 3)
            cv::cvtColor(in, file, cv::COLOR_RGB2BGR);
        else
            file = in;
        return encoded_copy(ext, file, "float ", len, err, err_size);
    } catch (const std::exception &e) {
        set_err(err, err_size, std::string("the float encoder failed: ") + e.what());
        return nullptr;
    }
}

static float *decode_f32(const uint8_t *data, size_t len, int *width, int *height, int *channels,
                         char *err, int err_size) {
    try {
        std::vector<uchar> buf(data, data + len);
        cv::Mat m = cv::imdecode(buf, cv::IMREAD_UNCHANGED);
        if (m.empty() || m.depth() != CV_32F || (m.channels() != 1 && m.channels() != 3)) {
            set_err(err, err_size, "not a float image of 1 or 3 channels (expected a .pfm file)");
            return nullptr;
        }
        if (m.channels() == 3) cv::cvtColor(m, m, cv::COLOR_BGR2RGB);
        m = m.clone(); /* continuous */
        size_t bytes = m.total() * m.elemSize();
        auto *out = static_cast<float *>(std::malloc(bytes ? bytes : 1));
        if (!out) {
            set_err(err, err_size, "out of memory for the decoded float image");
            return nullptr;
        }
        std::memcpy(out, m.data, bytes);
        *width = m.cols;
        *height = m.rows;
        *channels = m.channels();
        return out;
    } catch (const std::exception &e) {
        set_err(err, err_size, std::string("the float decoder failed: ") + e.what());
        return nullptr;
    }
}

static bool decode_size(const uint8_t *data, size_t len, int *width, int *height) {
    try {
        std::vector<uchar> buf(data, data + len);
        cv::Mat m = cv::imdecode(buf, cv::IMREAD_UNCHANGED);
        if (m.empty()) return false;
        *width = m.cols;
        *height = m.rows;
        return true;
    } catch (const std::exception &) {
        return false;
    }
}

static bool can_write(const char *path) {
    try {
        return cv::haveImageWriter(path);
    } catch (const cv::Exception &) {
        return false;
    }
}

static uint8_t *decode_rgb8(const uint8_t *data, size_t len, int *width, int *height, char *err,
                            int err_size) {
    try {
        // A corrupt file makes libpng / libjpeg print their own "libpng error:
        // ..." to stderr before imdecode returns empty: catch that text and
        // drop it when the decode fails (our message says it all), pass it on
        // when it succeeds (a warning about a good file).
        std::fflush(stderr);
        std::FILE *capture = std::tmpfile();
        int saved = capture ? dup(2) : -1;
        if (saved >= 0) dup2(fileno(capture), 2);
        cv::Mat bgr;
        bool too_big = false;
        try {
            const cv::Mat bytes(1, (int)len, CV_8UC1, const_cast<uint8_t *>(data));
            bgr = cv::imdecode(bytes, cv::IMREAD_COLOR);
        } catch (const cv::Exception &e) {
            // validateInputImageSize: over OPENCV_IO_MAX_IMAGE_PIXELS (set
            // from the memory budget, ras_memory.h) or the width/height limits.
            too_big = std::strstr(e.what(), "CV_IO_MAX_IMAGE") != nullptr;
            bgr.release();
        } catch (...) {
            bgr.release();
        }
        if (saved >= 0) {
            std::fflush(stderr);
            dup2(saved, 2);
            close(saved);
            if (!bgr.empty()) {
                std::rewind(capture);
                char buf[512];
                size_t n;
                while ((n = std::fread(buf, 1, sizeof buf, capture)) > 0)
                    std::fwrite(buf, 1, n, stderr);
            }
        }
        if (capture) std::fclose(capture);
        if (bgr.empty() && too_big) {
            const char *limit = std::getenv("OPENCV_IO_MAX_IMAGE_PIXELS");
            set_err(err, err_size,
                    std::string("its header announces more pixels than the decoder limit "
                                "(OPENCV_IO_MAX_IMAGE_PIXELS=") +
                        (limit ? limit : "?") +
                        ", set from the memory limit); use a smaller image or raise the limit "
                        "with --memory-limit MB");
            return nullptr;
        }
        if (bgr.empty()) {
            set_err(err, err_size,
                    "not an image OpenCV can decode (PNG, JPEG, BMP, ...), or a damaged one");
            return nullptr;
        }
        // BGR → RGB straight into the caller's buffer: one pass over the
        // pixels instead of cvtColor into a third buffer and a copy.
        size_t bytes = (size_t)bgr.rows * (size_t)bgr.cols * 3;
        auto *out = static_cast<uint8_t *>(std::malloc(bytes));
        if (!out) {
            set_err(err, err_size, "out of memory decoding image");
            return nullptr;
        }
        for (int r = 0; r < bgr.rows; r++) {
            const uint8_t *src = bgr.ptr<uint8_t>(r);
            uint8_t *dst = out + (size_t)r * (size_t)bgr.cols * 3;
            for (int c = 0; c < bgr.cols; c++, src += 3, dst += 3) {
                dst[0] = src[2];
                dst[1] = src[1];
                dst[2] = src[0];
            }
        }
        *width = bgr.cols;
        *height = bgr.rows;
        return out;
    } catch (const std::exception &e) {
        set_err(err, err_size, std::string("the decoder failed: ") + e.what());
        return nullptr;
    }
}

static bool window_show(const char *title, int width, int height, const uint8_t *rgb, char *err,
                        int err_size) {
    try {
        if (g_mouse.find(title) == g_mouse.end()) {
            cv::namedWindow(title, cv::WINDOW_AUTOSIZE);
            Mouse &m = g_mouse[title];
            cv::setMouseCallback(title, on_mouse, &m);
        }
        cv::Mat in(height, width, CV_8UC3, const_cast<uint8_t *>(rgb));
        cv::Mat bgr;
        cv::cvtColor(in, bgr, cv::COLOR_RGB2BGR);
        cv::imshow(title, bgr);
        return true;
    } catch (const cv::Exception &e) {
        set_err(err, err_size, std::string("could not open a window: ") + e.what());
        return false;
    }
}

// Whether the user closed the window. A property answering -1 means
// "unsupported" as well as "no such window", so -1 alone proves nothing:
// OpenCV 4.5.1's GTK backend (Debian 11) answers -1 to WND_PROP_VISIBLE for
// every window, open or not, and taking that as "closed" shut each window
// after its first frame. The window is closed when VISIBLE answers 0 (Qt;
// GTK from 4.5.2 on), when WND_PROP_AUTOSIZE — which every backend answers for
// a window it still has (1: opened WINDOW_AUTOSIZE) — has answered before and
// now answers -1 (the backend dropped the window: 4.5.1's GTK), or when asking
// throws (4.6's GTK for a window it no longer has). A backend answering
// neither leaves the window open until Esc or q, and says so once.
static bool window_closed(const char *title) {
    auto it = g_mouse.find(title);
    if (it == g_mouse.end()) return true;
    try {
        double visible = cv::getWindowProperty(title, cv::WND_PROP_VISIBLE);
        double autosize = cv::getWindowProperty(title, cv::WND_PROP_AUTOSIZE);
        if (visible >= 0 && visible < 1) return true;
        if (autosize >= 0) {
            it->second.autosize_answered = true;
            return false;
        }
        static bool told;
        if (!it->second.autosize_answered && visible < 0 && !told) {
            told = true;
            std::fprintf(stderr, "window: this OpenCV's window toolkit does not say when a window "
                                 "is closed; close it with Esc or q\n");
        }
        return it->second.autosize_answered;
    } catch (const cv::Exception &) {
        return true;
    }
}

static int window_wait_key(const char *title, int ms) {
    int key = cv::waitKey(ms);
    if (window_closed(title)) return -2;
    return key < 0 ? -1 : (key & 0xFF);
}

static void window_close(const char *title) {
    try {
        cv::destroyWindow(title);
    } catch (const cv::Exception &) {
    }
    g_mouse.erase(title);
}

static bool window_mouse(const char *title, int *col, int *row) {
    auto it = g_mouse.find(title);
    if (it == g_mouse.end() || it->second.col < 0) return false;
    *col = it->second.col;
    *row = it->second.row;
    return true;
}

static void draw_text(uint8_t *rgb, int width, int height, int col, int row, const char *text,
                      double scale) {
    cv::Mat img(height, width, CV_8UC3, rgb);
    // A dark outline under the white text keeps it readable on any picture.
    cv::putText(img, text, cv::Point(col, row), cv::FONT_HERSHEY_SIMPLEX, scale,
                cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
    cv::putText(img, text, cv::Point(col, row), cv::FONT_HERSHEY_SIMPLEX, scale,
                cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
}

// The one exported symbol (cv_bridge.h, CV_BRIDGE_MODULE_SYMBOL).
extern "C" __attribute__((visibility("default"))) const cv_bridge_table *
cv_bridge_module_table(void) {
    static const cv_bridge_table table = {
        /* in cv_bridge_table's order */
        CV_BRIDGE_ABI, encode_rgb8, decode_size,     can_write,    decode_rgb8,  encode_f32,
        decode_f32,    window_show, window_wait_key, window_close, window_mouse, draw_text,
    };
    return &table;
}
