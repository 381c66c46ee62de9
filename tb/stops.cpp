#include "stops.h"

#include <signal.h>
#include <sys/time.h>
#include <unistd.h>

#include <cstring>

#include "messages.h"
#include "output_file.h"
#include "subprocess.h"
#include "wall_limit.h"
#include "process/watchdog.h"

namespace rt {
namespace {

volatile sig_atomic_t orderly = 0;

// Async-signal-safe line writing: fixed buffers, no allocation.
struct Line {
    char buf[256];
    size_t n = 0;
    Line& operator<<(const char* s) {
        while (*s && n + 1 < sizeof buf) buf[n++] = *s++;
        return *this;
    }
    Line& operator<<(long v) {
        char digits[24];
        int k = 0;
        if (v < 0) {
            *this << "-";
            v = -v;
        }
        do digits[k++] = char('0' + v % 10); while ((v /= 10) && k < 23);
        while (k && n + 1 < sizeof buf) buf[n++] = digits[--k];
        return *this;
    }
    // Seconds as "1", "0.3" or "2.125": up to three decimals.
    Line& seconds(double s) {
        const long ms = long(s * 1000 + 0.5);
        *this << ms / 1000;
        if (ms % 1000) {
            char frac[5] = {'.', char('0' + ms / 100 % 10), char('0' + ms / 10 % 10), char('0' + ms % 10), 0};
            for (int i = 3; i > 0 && frac[i] == '0'; --i) frac[i] = 0;
            *this << frac;
        }
        return *this;
    }
};

const char* nameOf(int sig) { return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "a signal"; }

[[noreturn]] void endNow(int sig, bool second) {
    removeTempFilesNow();
    signalChildrenNow(SIGKILL);
    Line l;
    if (sig == SIGALRM) {
        l << msg::program() << ": error: watchdog: the wall-clock limit of ";
        l.seconds(wallLimitSeconds()) << " s was reached during start-up\n";
    } else {
        l << msg::program() << ": stopped by signal " << long(sig) << " (" << nameOf(sig) << ")"
          << (second ? " a second time: at once" : " during start-up") << "\n";
    }
    if (::write(2, l.buf, l.n) < 0) {
    }
    _exit(sig == SIGALRM ? 3 : 128 + sig);
}

extern "C" void onStop(int sig) {
    if (sig == SIGALRM) {  // --watchdog-wall: ends a start-up, asks a running machine to stop
        if (!orderly && !simulationRunning) endNow(sig, false);
        wallExpired = 1;  // (child runs keep their own share of the limit)
        return;
    }
    const bool second = stopSignal != 0;
    if (!second) stopSignal = sig;
    if (second || (!orderly && !simulationRunning)) endNow(sig, second);
    signalChildrenNow(sig);
}

}  // namespace

void installStopHandlers() {
    programStart();
    struct sigaction stop {};
    stop.sa_handler = onStop;
    sigemptyset(&stop.sa_mask);
    for (int s : {SIGINT, SIGTERM, SIGALRM}) sigaddset(&stop.sa_mask, s);
    for (int s : {SIGINT, SIGTERM, SIGALRM}) sigaction(s, &stop, nullptr);
}

void setWallLimit(double seconds) {
    recordWallLimit(seconds);
    if (seconds <= 0) return;
    const double left = seconds - wallElapsed();
    itimerval t{};
    t.it_value.tv_sec = left > 0 ? time_t(left) : 0;
    t.it_value.tv_usec = left > 0 ? suseconds_t((left - double(time_t(left))) * 1e6) : 1;
    if (t.it_value.tv_sec == 0 && t.it_value.tv_usec == 0) t.it_value.tv_usec = 1;
    setitimer(ITIMER_REAL, &t, nullptr);
}

OrderlyStops::OrderlyStops() : before_(orderly) { orderly = 1; }
OrderlyStops::~OrderlyStops() { orderly = before_; }

}  // namespace rt
