#pragma once
// A declaration-only stand-in for OpenHaptics' HD/hd.h (3D Systems' HD API): exactly the part that
// devices/drivers/openhaptics_device.cpp is allowed to use, so that a compile-only check shows the
// skeleton builds against that API on machines without the SDK. Nothing here is defined: the object
// file it produces must never be linked.
//
// Names, types and values follow the SDK's headers (hdDefines.h, hdDevice.h, hdScheduler.h); the
// driver depends on the names only.

#ifdef __cplusplus
extern "C" {
#endif

typedef unsigned int HDuint;
typedef int HDint;
typedef double HDdouble;
typedef unsigned int HDenum;
typedef unsigned int HDerror;
typedef const char* HDstring;
typedef HDuint HHD;  // a device handle

typedef struct {
  HDerror errorCode;      // HD_SUCCESS when there is no error
  int internalErrorCode;  // the driver's own code, for 3D Systems' support
  HHD hHD;                // the device the error concerns
} HDErrorInfo;

#define HD_SUCCESS 0x0000
#define HD_DEVICE_ERROR(X) (((X).errorCode) != HD_SUCCESS)
#define HD_DEFAULT_DEVICE ((HDstring)0)

// Capabilities (hdEnable).
#define HD_FORCE_OUTPUT 0x4000

// Parameters (hdGet*, hdSet*).
#define HD_CURRENT_BUTTONS 0x2000    // HDint bit mask, bit i = button i + 1
#define HD_CURRENT_POSITION 0x2050   // HDdouble[3], [mm], device frame
#define HD_CURRENT_TRANSFORM 0x2052  // HDdouble[16], column-major 4x4, translation in [mm]
#define HD_NOMINAL_MAX_FORCE 0x2603  // HDdouble, [N]
#define HD_CURRENT_FORCE 0x2700      // HDdouble[3], [N], device frame

HHD hdInitDevice(HDstring pConfigName);
void hdDisableDevice(HHD hHD);
HDErrorInfo hdGetError(void);
HDstring hdGetErrorString(HDerror errorCode);
void hdEnable(HDenum cap);
void hdStartScheduler(void);
void hdStopScheduler(void);
void hdBeginFrame(HHD hHD);
void hdEndFrame(HHD hHD);
void hdGetDoublev(HDenum pname, HDdouble* params);
void hdGetIntegerv(HDenum pname, HDint* params);
void hdSetDoublev(HDenum pname, const HDdouble* params);

#ifdef __cplusplus
}
#endif
