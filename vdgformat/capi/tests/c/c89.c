/*
 * c89.c: the header under the oldest C a game engine may still build with
 * (-std=c89 -pedantic -Wall -Wextra -Werror), and the lifetime of the error
 * string: a pointer from vdg_last_error() stays readable after later failing
 * calls, which overwrite the text in place. Compiled and run by
 * tests/c_smoke.rs; prints "ok" and exits 0 when every check holds.
 */
#include <stdio.h>
#include <string.h>

#include "vdg.h"

static int failures = 0;

static void expect(int ok, const char *what)
{
    if (!ok) {
        printf("FAILED: %s\n", what);
        failures++;
    }
}

int main(void)
{
    const char *first;
    char kept[64];
    float c;

    expect(VDG_ABI_VERSION == vdg_abi_version(), "VDG_ABI_VERSION matches the library");
    expect(vdg_version() != NULL && strlen(vdg_version()) > 0, "vdg_version names a version");

    c = vdg_clearance(NULL, NULL);
    expect(c != c, "vdg_clearance(NULL) is NaN");
    first = vdg_last_error();
    strncpy(kept, first, sizeof kept - 1);
    kept[sizeof kept - 1] = '\0';
    expect(strstr(first, "vdg_clearance") != NULL, "the first message names vdg_clearance");

    /* A second failing call: the first pointer is still readable and now
     * holds the newer message (valgrind: no invalid read). */
    expect(vdg_open(NULL) == NULL, "vdg_open(NULL) fails");
    expect(strstr(first, "vdg_open") != NULL, "the old pointer shows the new message");
    expect(first == vdg_last_error(), "one buffer per thread");
    expect(strstr(kept, "vdg_clearance") != NULL, "a copy keeps the first message");

    /* The pattern of the report: the arguments' order of evaluation is
     * unspecified, and either way the text is readable. */
    printf("%f %s\n", (double)vdg_clearance(NULL, NULL), vdg_last_error());

    if (failures == 0) {
        printf("ok\n");
    }
    return failures == 0 ? 0 : 1;
}
