#include <body_scan_driver/hw/usb_bus.h>
#include <libusb.h>

#include <cstdio>
#include <stdexcept>

namespace body_scan_driver::hw {

std::string vendorProduct(uint16_t vendor_id, uint16_t product_id) {
  char text[10];
  std::snprintf(text, sizeof text, "%04x:%04x", vendor_id, product_id);
  return text;
}

UsbDeviceMatch UsbDeviceMatch::parse(const std::string& vendor_product, const std::string& serial) {
  unsigned vendor = 0, product = 0;
  char end = 0;
  if (vendor_product.size() != 9 ||
      std::sscanf(vendor_product.c_str(), "%4x:%4x%c", &vendor, &product, &end) != 2)
    throw std::invalid_argument("USB id '" + vendor_product +
                                "' is not vendor:product in hex, e.g. 046d:0825 (see "
                                "`rosrun body_scan_driver list_devices`)");
  UsbDeviceMatch match;
  match.vendor_id = static_cast<uint16_t>(vendor);
  match.product_id = static_cast<uint16_t>(product);
  match.serial = serial;
  return match;
}

bool UsbDeviceMatch::matches(const UsbDeviceInfo& device) const {
  return device.vendor_id == vendor_id && device.product_id == product_id &&
         (serial.empty() || device.serial == serial);
}

std::string UsbDeviceMatch::describe() const {
  const std::string id = vendorProduct(vendor_id, product_id);
  return serial.empty() ? id : id + "/" + serial;
}

std::optional<UsbDeviceInfo> findDevice(const std::vector<UsbDeviceInfo>& devices,
                                        const UsbDeviceMatch& match) {
  for (const UsbDeviceInfo& device : devices)
    if (match.matches(device)) return device;
  return std::nullopt;
}

namespace {

constexpr uint8_t kVideoClass = 0x0e;  // USB video class (UVC)

bool hasVideoInterface(libusb_device* device) {
  libusb_config_descriptor* config = nullptr;
  if (libusb_get_active_config_descriptor(device, &config) != LIBUSB_SUCCESS &&
      libusb_get_config_descriptor(device, 0, &config) != LIBUSB_SUCCESS)
    return false;
  bool video = false;
  for (int i = 0; i < config->bNumInterfaces && !video; ++i)
    for (int a = 0; a < config->interface[i].num_altsetting && !video; ++a)
      video = config->interface[i].altsetting[a].bInterfaceClass == kVideoClass;
  libusb_free_config_descriptor(config);
  return video;
}

class LibusbBus : public UsbBus {
 public:
  LibusbBus() {
    const int error = libusb_init(&context_);
    if (error != LIBUSB_SUCCESS) {
      context_ = nullptr;
      init_error_ = std::string("libusb could not start: ") + libusb_strerror(error) +
                    " (in a container, mount /dev/bus/usb and run with access to it)";
    }
  }
  ~LibusbBus() override {
    if (!context_) return;
    if (hotplug_registered_) libusb_hotplug_deregister_callback(context_, hotplug_handle_);
    libusb_exit(context_);
  }

  std::vector<UsbDeviceInfo> devices() override {
    if (!context_) throw std::runtime_error(init_error_);
    libusb_device** list = nullptr;
    const ssize_t count = libusb_get_device_list(context_, &list);
    if (count < 0)
      throw std::runtime_error(std::string("cannot list USB devices: ") +
                               libusb_strerror(static_cast<int>(count)));
    std::vector<UsbDeviceInfo> devices;
    for (ssize_t i = 0; i < count; ++i) {
      libusb_device_descriptor descriptor;
      if (libusb_get_device_descriptor(list[i], &descriptor) != LIBUSB_SUCCESS) continue;
      UsbDeviceInfo info;
      info.vendor_id = descriptor.idVendor;
      info.product_id = descriptor.idProduct;
      info.bus = libusb_get_bus_number(list[i]);
      info.address = libusb_get_device_address(list[i]);
      info.is_uvc = hasVideoInterface(list[i]);
      // The serial needs the device opened; without permission (udev rules) it stays empty.
      libusb_device_handle* handle = nullptr;
      if (descriptor.iSerialNumber != 0 && libusb_open(list[i], &handle) == LIBUSB_SUCCESS) {
        unsigned char serial[256];
        const int length = libusb_get_string_descriptor_ascii(handle, descriptor.iSerialNumber,
                                                              serial, sizeof serial);
        if (length > 0) info.serial.assign(reinterpret_cast<char*>(serial), length);
        libusb_close(handle);
      }
      devices.push_back(info);
    }
    libusb_free_device_list(list, 1);
    return devices;
  }

  bool hasHotplug() const override {
    return context_ && libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG);
  }

  void setChangeCallback(std::function<void()> on_change) override {
    on_change_ = std::move(on_change);
    if (!hasHotplug() || hotplug_registered_) return;
    const int error = libusb_hotplug_register_callback(
        context_,
        static_cast<libusb_hotplug_event>(LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED |
                                          LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT),
        LIBUSB_HOTPLUG_NO_FLAGS, LIBUSB_HOTPLUG_MATCH_ANY, LIBUSB_HOTPLUG_MATCH_ANY,
        LIBUSB_HOTPLUG_MATCH_ANY, &LibusbBus::onHotplug, this, &hotplug_handle_);
    hotplug_registered_ = error == LIBUSB_SUCCESS;
  }

  void handleEvents() override {
    if (!hotplug_registered_) return;
    timeval zero{0, 0};
    libusb_handle_events_timeout_completed(context_, &zero, nullptr);
  }

 private:
  static int LIBUSB_CALL onHotplug(libusb_context*, libusb_device*, libusb_hotplug_event,
                                   void* user) {
    auto* self = static_cast<LibusbBus*>(user);
    if (self->on_change_) self->on_change_();
    return 0;  // stay registered
  }

  libusb_context* context_ = nullptr;
  std::string init_error_;
  std::function<void()> on_change_;
  bool hotplug_registered_ = false;
  libusb_hotplug_callback_handle hotplug_handle_{};
};

}  // namespace

std::unique_ptr<UsbBus> makeLibusbBus() { return std::make_unique<LibusbBus>(); }

}  // namespace body_scan_driver::hw
