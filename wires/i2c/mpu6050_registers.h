// The MPU-6050's register addresses and bits that the model acts on, from
// InvenSense's "MPU-6000 and MPU-6050 Register Map and Descriptions",
// document RM-MPU-6000A-00, revision 4.2 (2013-08-19), sections 3 and 4.
#pragma once

#include <cstdint>

namespace tcs::mpu6050 {

constexpr uint8_t kAddress = 0x68; // AD0 low; 0x69 with AD0 high

constexpr uint8_t kSelfTestX = 0x0D;
constexpr uint8_t kSmplrtDiv = 0x19;
constexpr uint8_t kConfig = 0x1A;     // DLPF_CFG bits 2:0
constexpr uint8_t kGyroConfig = 0x1B; // FS_SEL bits 4:3
constexpr uint8_t kAccelConfig = 0x1C; // AFS_SEL bits 4:3
constexpr uint8_t kFifoEn = 0x23;
constexpr uint8_t kI2cSlv4Di = 0x35;
constexpr uint8_t kI2cMstStatus = 0x36;
constexpr uint8_t kIntPinCfg = 0x37; // INT_RD_CLEAR bit 4
constexpr uint8_t kIntEnable = 0x38; // DATA_RDY_EN bit 0
constexpr uint8_t kIntStatus = 0x3A; // DATA_RDY_INT bit 0
constexpr uint8_t kAccelXoutH = 0x3B;
constexpr uint8_t kTempOutH = 0x41;
constexpr uint8_t kGyroXoutH = 0x43;
constexpr uint8_t kExtSensData00 = 0x49;
constexpr uint8_t kI2cSlv0Do = 0x63;
constexpr uint8_t kSignalPathReset = 0x68;
constexpr uint8_t kUserCtrl = 0x6A;  // SIG_COND_RESET bit 0, I2C_MST_RESET bit 1, FIFO_RESET bit 2
constexpr uint8_t kPwrMgmt1 = 0x6B;  // DEVICE_RESET bit 7, SLEEP bit 6, CYCLE bit 5, TEMP_DIS bit 3, CLKSEL 2:0
constexpr uint8_t kPwrMgmt2 = 0x6C;  // STBY_XA..ZA bits 5:3, STBY_XG..ZG bits 2:0
constexpr uint8_t kFifoCountH = 0x72;
constexpr uint8_t kFifoCountL = 0x73;
constexpr uint8_t kFifoRW = 0x74;
constexpr uint8_t kWhoAmI = 0x75;

constexpr uint8_t kDeviceReset = 0x80;
constexpr uint8_t kSleep = 0x40;
constexpr uint8_t kTempDis = 0x08;
constexpr uint8_t kClkStop = 0x07; // CLKSEL 7: the clock stopped
constexpr uint8_t kIntRdClear = 0x10;
constexpr uint8_t kDataRdy = 0x01;
constexpr uint8_t kSigCondReset = 0x01;
constexpr uint8_t kUserCtrlResets = 0x07; // the three reset bits, which clear themselves

constexpr uint8_t kPwrMgmt1Reset = 0x40; // asleep
constexpr uint8_t kWhoAmIValue = 0x68;

// g in m/s² (the standard gravity, 9.80665 exactly) for the accelerometer's LSB/g.
constexpr double kStandardGravity = 9.80665;

} // namespace tcs::mpu6050
