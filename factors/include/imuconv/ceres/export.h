// Symbol visibility for imuconv's Ceres library (imuconv::ceres), like imuconv/export.h for the
// core: everything is hidden by default (-fvisibility=hidden); only what carries
// IMUCONV_CERES_API is exported.
#pragma once

#define IMUCONV_CERES_API __attribute__((visibility("default")))
