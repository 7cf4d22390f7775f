// Symbol visibility for the imuconv shared libraries. Everything is hidden by
// default (-fvisibility=hidden); only what carries IMUCONV_API is exported.
#pragma once

#if defined(IMUCONV_BUILDING_LIBRARY) || defined(IMUCONV_STATIC)
#define IMUCONV_API __attribute__((visibility("default")))
#else
#define IMUCONV_API __attribute__((visibility("default")))
#endif
