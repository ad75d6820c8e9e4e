/* grade_results.h — the items raster101-grade scores (tests/grading/grade_*.c):
 * an assignment's list of items, an item's JUnit <testcase>, the totals.
 * The types are grade_priv.h's.
 */
#ifndef RAS_GRADING_GRADE_RESULTS_H
#define RAS_GRADING_GRADE_RESULTS_H

#include "grade_priv.h"

/* a new item at the end of a's list: zeroed, counted */
item *add_item(assignment_result *a);
void item_free(item *it);
/* the n results of `as` and what they own, then `as` itself */
void assignment_results_free(assignment_result *as, int n);
/* it->xml: raw_xml as it is, or a <testcase> made from the item */
void junit_case(item *it, const char *classname, const char *raw_xml);
/* a->score and a->max_score increased by its counted items' */
void add_up(assignment_result *a);

#endif
