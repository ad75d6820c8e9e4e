# The PrairieLearn grading image of Raster101 (tests/grading/make-prairielearn
# copies this file to build/prairielearn/Dockerfile; docs/instructors.md
# "PrairieLearn"). Built from build/prairielearn/ as the context:
#   docker build -t raster101-grader build/prairielearn
# Debian 12 with the project's packages (scripts/install-deps) and the trusted
# side of the grader built once, here, at /opt/raster101-build: a grading job
# then only builds and runs the student's code (in the sandbox), well within
# PrairieLearn's 600 s. The tree is the package's serverFilesCourse/raster101,
# so the image and the course's entrypoint come from one package (PACKAGE_ID).
FROM debian:12
COPY serverFilesCourse/raster101 /opt/raster101
RUN /opt/raster101/scripts/install-deps \
 && /opt/raster101/tests/grading/grade --build /opt/raster101-build \
      --out /opt/raster101-build/setup --build-trusted-only \
 && cmake --build /opt/raster101-build --target raster101-pl-results \
 && rm -rf /var/lib/apt/lists/*
# The sandbox's template: the TODO stubs' tree configured and built in the
# sandbox once, here, so that each grading copies it and recompiles only the
# student's file (a hw1 grading 13-16 s -> 3-5 s on the project's 2-core machine, issue 37).
# If it cannot be made here the image still builds (said), and each grading
# builds the sandbox's tree in full, as pl-grade's grade says.
RUN /opt/raster101/tests/grading/grade --build /opt/raster101-build --trusted-ready \
      --out /opt/raster101-build/setup-template --save-template /opt/raster101-template \
 || echo "raster101: the sandbox's template could not be made (log in /opt/raster101-build/setup-template): each grading builds in full"
ENV RAS_PL_TREE=/opt/raster101 RAS_PL_BUILD=/opt/raster101-build RAS_PL_TEMPLATE=/opt/raster101-template
