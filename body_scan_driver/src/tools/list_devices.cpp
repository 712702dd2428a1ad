// Lists the attached USB devices, so a pair can be configured with the right vendor:product
// and serial:   rosrun body_scan_driver list_devices [--uvc]
#include <body_scan_driver/hw/usb_bus.h>
#include <body_scan_driver/tools/command_line.h>

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  CLI::App app("Lists the attached USB devices (vendor:product, serial, bus/address, UVC).",
               "list_devices");
  bool only_uvc = false;
  app.add_flag("--uvc", only_uvc, "cameras only (devices with a UVC interface)");
  if (const auto status = body_scan_driver::tools::parseCommandLine(app, argc, argv))
    return *status;
  try {
    const auto bus = body_scan_driver::hw::makeLibusbBus();
    const auto devices = bus->devices();
    std::printf("%-10s %-24s %-8s %-4s\n", "id", "serial", "bus/addr", "uvc");
    int shown = 0;
    for (const auto& device : devices) {
      if (only_uvc && !device.is_uvc) continue;
      char where[16];
      std::snprintf(where, sizeof where, "%03d/%03d", device.bus, device.address);
      std::printf("%-10s %-24s %-8s %-4s\n",
                  body_scan_driver::hw::vendorProduct(device.vendor_id, device.product_id).c_str(),
                  device.serial.empty() ? "-" : device.serial.c_str(), where,
                  device.is_uvc ? "yes" : "no");
      ++shown;
    }
    std::printf(
        "%d device(s)%s; hot-plug %s. A serial shown as '-' has none or needs read "
        "permission (install udev/99-body-scan.rules).\n",
        shown, only_uvc ? " with a UVC interface" : "",
        bus->hasHotplug() ? "supported" : "not supported (the driver polls)");
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "list_devices: %s\n", e.what());
    return 1;
  }
}
