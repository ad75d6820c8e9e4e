/* grade_results.c — the items raster101-grade scores (grade_results.h). */
#include "grade_results.h"

#include "grade_base.h"
#include "grade_text.h"

#include <stdlib.h>
#include <string.h>

item *add_item(assignment_result *a) {
    if (a->n_items == a->cap_items) {
        a->cap_items = a->cap_items ? 2 * a->cap_items : 16;
        a->items = realloc(a->items, (size_t)a->cap_items * sizeof *a->items);
        if (!a->items) abort();
    }
    item *it = &a->items[a->n_items++];
    memset(it, 0, sizeof *it);
    it->counted = true;
    return it;
}

void item_free(item *it) {
    char *owned[] = {it->name,         it->status,  it->reason,   it->output,   it->xml,
                     it->img_expected, it->img_got, it->img_diff, it->img_crop, it->buf_name,
                     it->buf_ref,      it->buf_got, it->buf_diff};
    for (size_t i = 0; i < sizeof owned / sizeof owned[0]; i++)
        free(owned[i]);
}

void assignment_results_free(assignment_result *as, int n) {
    for (int k = 0; k < n; k++) {
        for (int i = 0; i < as[k].n_items; i++)
            item_free(&as[k].items[i]);
        free(as[k].items);
        free(as[k].id);
        free(as[k].title);
        free(as[k].note);
    }
    free(as);
}

void junit_case(item *it, const char *classname, const char *raw_xml) {
    sbuf x = {0};
    if (raw_xml) {
        sb_add(&x, raw_xml);
    } else {
        sb_add(&x, "    <testcase classname=\"");
        xml_escape(&x, classname);
        sb_add(&x, "\" name=\"");
        xml_escape(&x, it->name);
        sb_add(&x, "\">\n");
        if (!it->passed) {
            sb_add(&x, "      <failure message=\"");
            xml_escape(&x, it->reason ? it->reason : it->status);
            sb_add(&x, "\"><![CDATA[");
            sb_add(&x, it->output ? it->output : "");
            sb_add(&x, "]]></failure>\n");
        }
        sb_add(&x, "    </testcase>\n");
    }
    it->xml = x.s;
}

void add_up(assignment_result *a) {
    for (int i = 0; i < a->n_items; i++)
        if (a->items[i].counted) {
            a->score += a->items[i].score;
            a->max_score += a->items[i].max_score;
        }
}
