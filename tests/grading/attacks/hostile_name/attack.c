/* A hostile student name: this submission is the stub; run-attacks puts it
 * into the grade-all batch under names that collide with the batch's own
 * files or that a shell or a CSV would misread (gradebook.csv.tmp, students,
 * -rf, "a b;c", "x,y"), and checks every student still gets a row. */
