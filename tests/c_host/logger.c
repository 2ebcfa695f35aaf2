/* The tests' fmi2CallbackLogger: a real C-variadic function, as a host's is. It formats the
 * message with its arguments (vsnprintf: the message is a printf format, FMI 2.0 section 2.1.5)
 * and hands the finished text to the sink the test installed. Built into a shared object by
 * tests/common/c_logger.rs at run time. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

typedef void (*bindery_sink)(void *env, const char *instance, int status, const char *category,
                             const char *text);

static bindery_sink sink;

void bindery_test_set_sink(bindery_sink s) { sink = s; }

void bindery_test_logger(void *env, const char *instance, int status, const char *category,
                         const char *message, ...) {
    char buf[4096];
    char *text = buf;
    va_list ap, again;
    va_start(ap, message);
    va_copy(again, ap);
    if (!message) {
        va_end(ap);
        va_end(again);
        if (sink) sink(env, instance, status, category, NULL);
        return;
    }
    int n = vsnprintf(buf, sizeof buf, message, ap);
    va_end(ap);
    if (n >= (int)sizeof buf) {
        char *big = malloc((size_t)n + 1);
        if (big) {
            vsnprintf(big, (size_t)n + 1, message, again);
            text = big;
        }
    }
    va_end(again);
    if (sink) sink(env, instance, status, category, text);
    if (text != buf) free(text);
}
