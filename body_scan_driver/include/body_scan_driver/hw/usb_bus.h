// The USB bus as the hardware backend sees it: a list of attached devices and a "something
// changed" signal. libusb sits behind this interface (makeLibusbBus) so that the connection
// logic is unit-tested with a fake bus.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace body_scan_driver::hw {

struct UsbDeviceInfo {
  uint16_t vendor_id = 0, product_id = 0;
  std::string serial;  // empty when the device has none or it could not be read
  int bus = 0, address = 0;
  bool is_uvc = false;  // has a USB video class interface (a camera libuvc can open)
};

// "vvvv:pppp" in lower-case hex, e.g. "046d:0825".
std::string vendorProduct(uint16_t vendor_id, uint16_t product_id);

// Which device a pair is configured for: vendor:product and optionally a serial number.
struct UsbDeviceMatch {
  uint16_t vendor_id = 0, product_id = 0;
  std::string serial;  // empty: the first device with this vendor:product

  // Parses "vvvv:pppp" (hex). Throws std::invalid_argument naming the text and the format.
  static UsbDeviceMatch parse(const std::string& vendor_product, const std::string& serial);
  bool matches(const UsbDeviceInfo& device) const;
  // "vvvv:pppp/SERIAL" or "vvvv:pppp" without a serial: the name used in every message.
  std::string describe() const;
};

class UsbBus {
 public:
  virtual ~UsbBus() = default;
  // Every attached device. Throws std::runtime_error if the bus cannot be read.
  virtual std::vector<UsbDeviceInfo> devices() = 0;
  // Whether arrivals and departures are signalled (hot-plug); otherwise callers poll.
  virtual bool hasHotplug() const = 0;
  // Called (from handleEvents) when a device arrives or leaves; only with hasHotplug().
  virtual void setChangeCallback(std::function<void()> on_change) = 0;
  // Dispatches pending hot-plug events without blocking.
  virtual void handleEvents() = 0;
};

std::optional<UsbDeviceInfo> findDevice(const std::vector<UsbDeviceInfo>& devices,
                                        const UsbDeviceMatch& match);

// libusb-1.0. Does not throw: if libusb cannot start (e.g. no /dev/bus/usb in a container),
// devices() throws with the reason, so a driver keeps retrying instead of dying.
std::unique_ptr<UsbBus> makeLibusbBus();

}  // namespace body_scan_driver::hw
